#pragma once
/// A slice of the scene coloured inside / outside (the lecture's inside/outside query
/// seen whole): a plane across the scene's box, perpendicular to one axis, sampled on
/// a grid of points, each classified by the ray-parity vote of inside.h (three rays,
/// every crossing counted through the BVH or brute force). On a closed mesh the inside
/// samples draw its cross-section; where the three rays disagree (a mesh with holes, or
/// a ray through an edge) the vote's count shows it.

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/mesh.h"
#include "core/render/image.h"
#include "core/util/expected.h"

namespace accelviz {

struct SliceSpec {
    int axis = 2;          ///< the plane is perpendicular to x (0), y (1) or z (2)
    float fraction = 0.5f;  ///< where along that axis, 0..1 of the mesh's box
    int columns = 128, rows = 128;
    bool operator==(const SliceSpec&) const = default;
};

struct InsideSlice {
    SliceSpec spec;
    float position = 0;    ///< the plane's coordinate on `spec.axis`
    int u_axis = 0, v_axis = 1;  ///< the plane's axes: columns go along u, rows along v (row 0 at v's top)
    float u_lo = 0, u_hi = 0, v_lo = 0, v_hi = 0;  ///< the rectangle: the mesh's box grown by a tenth
    std::vector<uint8_t> votes;  ///< per sample (row-major): how many of the three rays say inside
    uint64_t rays = 0, nodes_visited = 0, triangle_tests = 0;  ///< the work of the whole slice

    /// The point sampled at column c, row r (the centre of its cell).
    Vec3 sample(int c, int r) const;
    /// The rectangle's corners, counter-clockwise from (u_lo, v_lo).
    std::array<Vec3, 4> corners() const;
    bool inside(int c, int r) const { return votes[size_t(r) * size_t(spec.columns) + size_t(c)] >= 2; }
};

/// Whether `accel` counts crossings for the slice: the binary BVH, or naive (brute force).
bool has_crossing_count(const Accelerator& accel);

/// The slice through `accel` (built over `mesh`; has_crossing_count()), on all threads
/// (the same votes on any number). An error for a bad spec, another structure, or when
/// `cancel` turns true (checked per row).
Expected<InsideSlice> inside_slice(const Accelerator& accel, const Mesh& mesh, const SliceSpec& spec,
                                   const std::atomic<bool>* cancel = nullptr);

/// The colour of a sample with `votes` of three rays saying inside: inside (3) orange,
/// outside (0) dark blue, the split votes (2, 1) lighter shades of each.
Rgb slice_colour(int votes);

/// The slice as an image `width` x `height` (each pixel the nearest sample), with a
/// title and the colours' legend.
Image slice_view(const InsideSlice& slice, int width, int height);

}  // namespace accelviz
