#pragma once
/// Triangle references of the space-partitioning trees (KD tree, octree) while
/// they are built: which part of a triangle lies in a node, and how a reference
/// follows a split. A triangle that straddles a split plane goes to both sides
/// (lecture: 同一个基元可以包含在空间的多个区域中), with its box clipped to each side.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry/mesh.h"

namespace accelviz {

/// How a straddling triangle's box is cut down to a child.
enum class ClipMode : uint8_t {
    Box,    ///< box ∩ child box: cheap, keeps corners the triangle never reaches
    Exact,  ///< the triangle polygon clipped to the child, then its bounds ("perfect splits", Wald & Havran 2006)
};
std::string_view to_string(ClipMode mode);
std::optional<ClipMode> parse_clip_mode(std::string_view name);
const std::vector<std::string>& clip_mode_names();  ///< "box", "exact"

/// A triangle in a node under construction.
/// Invariant: `box` is the bounds of (triangle ∩ (node box grown by pad)),
/// grown by pad again. So, for a split plane s on axis a, the triangle comes
/// within pad of the lower child iff box.lo[a] < s, of the upper iff box.hi[a] > s
/// (both: it straddles). See reference_padding() for why the margin exists.
struct SpatialRef {
    uint32_t tri;
    Aabb box;
};

/// The references of a whole mesh in its root box `root` (the scene box grown by pad).
std::vector<SpatialRef> root_references(const Mesh& mesh, float pad);

/// `ref` restricted to `child` (a box inside the node `ref` belongs to), or
/// nothing if the triangle does not come within pad of `child` (possible with
/// Exact: the box reaches the child, the triangle does not).
std::optional<SpatialRef> clip_reference(const SpatialRef& ref, const Mesh& mesh, const Aabb& child, float pad,
                                         ClipMode mode);

}  // namespace accelviz
