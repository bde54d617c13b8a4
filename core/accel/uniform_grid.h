#pragma once
/// The uniform grid (lecture: 均匀网格划分): find the scene's box, cut it into
/// #cells ≈ C·#triangles cells (C ≈ 27 in 3D), store in each cell the triangles
/// that overlap it, and walk the cells along the ray in order with a 3D-DDA
/// (Amanatides & Woo 1987, "A Fast Voxel Traversal Algorithm for Ray Tracing").
///
/// Its weakness is the lecture's "teapot in a stadium" (体育场里的茶壶问题): the
/// resolution follows the triangle count, not where the triangles are, so a small
/// detailed object gets a handful of crowded cells while the rest stays empty.
/// The stats show it (max triangles per cell, empty %), and a cap that changes
/// the lecture's rule is reported in `notes`, never applied silently.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/accel/accel_type.h"
#include "core/accel/cell_hits.h"
#include "core/geometry/mesh.h"
#include "core/util/work_progress.h"
#include "core/util/expected.h"
#include "core/util/large_array.h"

namespace accelviz {

/// Which cells a triangle is stored in.
enum class GridInsert : uint8_t {
    Box,    ///< every cell its bounding box overlaps (cheap, many false references)
    Exact,  ///< every cell the triangle itself overlaps (separating axis test)
};
std::string_view to_string(GridInsert insert);
std::optional<GridInsert> parse_grid_insert(std::string_view name);
const std::vector<std::string>& grid_insert_names();  ///< "box", "exact"

/// Build and traversal parameters of the grid.
struct GridConfig {
    float density = 27.0f;              ///< C in #cells ≈ C·#triangles (lecture: C ≈ 27 in 3D); > 0
    GridInsert insert = GridInsert::Box;  ///< which cells a triangle goes into
    bool mailbox = true;                ///< skip triangles this ray already tested in an earlier cell
    int max_cells_per_axis = 1024;      ///< resolution cap per axis (1..4096); reported in notes when it applies
    uint64_t max_cells = 1u << 24;      ///< cap on the total (16M cells: 64 MB of cell offsets); reported when it applies
    uint64_t max_references = 1u << 28; ///< a build needing more references (1 GB of ids) fails with an error

    bool operator==(const GridConfig&) const = default;
};

/// A one-line error if a field is out of range (names the CLI flag).
std::optional<Error> validate(const GridConfig& config);

/// What the build produced.
struct GridBuildStats {
    uint32_t triangles = 0;
    std::array<int, 3> cells_per_axis{0, 0, 0};
    uint64_t cells = 0;
    uint64_t requested_cells = 0;  ///< density · #triangles: the lecture's rule before any cap
    uint64_t empty_cells = 0;
    uint64_t references = 0;       ///< Σ over cells of the triangles stored there
    uint32_t max_per_cell = 0;
    double mean_per_cell = 0;      ///< references / cells
    double mean_per_nonempty_cell = 0;
    float padding = 0;             ///< the references' safety margin (reference_padding)
    uint64_t memory_bytes = 0;     ///< cell offsets + references + triangles + planes
    double build_ms = 0;
    std::vector<std::string> notes;  ///< e.g. "resolution capped: …"
};

/// The grid. Cell (i, j, k) has linear id i + nx·(j + ny·k); its triangles are
/// tri_ids[cell_start[id] .. cell_start[id + 1]) in increasing id order.
/// Invariants: planes[a] has cells_per_axis[a] + 1 increasing values, from
/// bounds.lo[a] to bounds.hi[a] (bounds = the scene's box grown by the padding);
/// triangle t is in cell c iff t comes within `padding` of c (box or exact test,
/// per config.insert). Empty scene: no cells.
struct UniformGrid : CellQueries<UniformGrid> {
    Aabb bounds;
    std::array<int, 3> res{0, 0, 0};             ///< cells per axis
    std::array<std::vector<float>, 3> planes;    ///< cell boundaries per axis
    /// The big arrays live on huge pages (core/util/large_array.h): the lecture's 27 N
    /// cells are tens of megabytes, and their page faults were a fifth of the build.
    std::vector<uint32_t, LargeArrayAllocator<uint32_t>> cell_start;  ///< prefix sums, size cells + 1
    std::vector<uint32_t, LargeArrayAllocator<uint32_t>> tri_ids;     ///< references, cell by cell
    TriangleArray triangles;             ///< by triangle id (make_triangles)
    CornerArray corners;                 ///< the same, as corners; only when triangle_test is watertight
    GridConfig build_config;
    GridBuildStats build_stats;
    TriangleTestKind triangle_test = TriangleTestKind::MollerTrumbore;  ///< which ray-triangle test the cells run

    static constexpr AccelType kType = AccelType::Grid;
    std::string name() const { return std::string(to_string(kType)); }
    nlohmann::json config() const;
    nlohmann::json stats() const;

    uint32_t cell_id(int i, int j, int k) const { return uint32_t(i + res[0] * (j + res[1] * k)); }
    Aabb cell_bounds(int i, int j, int k) const {
        return {{planes[0][i], planes[1][j], planes[2][k]}, {planes[0][i + 1], planes[1][j + 1], planes[2][k + 1]}};
    }

private:
    friend struct CellQueries<UniformGrid>;
    /// The walk (CellQueries: intersect_closest, intersect_any), with the triangle test
    /// chosen at compile time: the 3D-DDA walk, events EnterCell, TriangleTest,
    /// MailboxSkip, HitOutsideCell, NewClosest, Done.
    template <TriangleTestKind kTest, StopAt kStop, class Observer>
    Hit front_to_back(const Ray& ray, Observer& obs) const;
    /// The cell along `axis` holding coordinate x; on a boundary, the one the ray
    /// moves into (by the sign of its direction component `d`).
    int locate(int axis, float x, float d) const;
};

/// The cell boundaries along one axis: n + 1 values from lo to hi, lo + (hi - lo)·i/n
/// computed in double and rounded to float, the two ends exactly lo and hi. Computed
/// once, shared by the build and the walk (and by a grid read from a file).
std::vector<float> grid_axis_planes(float lo, float hi, int n);

/// Builds the grid. Errors: the reference budget (config.max_references) exceeded;
/// WorkProgress::cancelled_error() once `progress` (units: chunks of triangles per
/// pass) is cancelled.
Expected<UniformGrid> build_uniform_grid(const Mesh& mesh, const GridConfig& config,
                                         WorkProgress* progress = nullptr);

// ---------------------------------------------------------------------------
// The 3D-DDA walk.
// ---------------------------------------------------------------------------

template <TriangleTestKind kTest, StopAt kStop, class Observer>
Hit UniformGrid::front_to_back(const Ray& ray, Observer& obs) const {
    using Hits = CellHits<kTest, kStop>;
    if (cell_start.empty()) return Hits::missed(obs);
    const RayPrecomp pre(ray);
    const SlabResult box = slab_test(bounds, pre, ray.t_min, ray.t_max);
    obs.on({.kind = EventKind::BoxTest, .hit = box.hit(), .node = 0, .t_enter = box.t_enter, .t_exit = box.t_exit});
    // slab_test starts from [t_min, t_max], so a hit box is already clipped to the ray.
    if (!(box.t_enter <= box.t_exit)) {
        obs.on({.kind = EventKind::Cull, .reason = CullReason::MissedBox, .node = 0, .t_enter = box.t_enter,
                .t_exit = box.t_exit});
        return Hits::missed(obs);
    }
    Hits hits(ray, pre, triangles, corners, build_config.mailbox, /*strict_cell=*/true, uint32_t(triangles.size()));
    const float t_end = box.t_exit;

    // The first cell: where the ray enters the grid, or the one holding the origin.
    int cell[3], step[3];
    float t_next[3];  // where the ray crosses the next boundary on each axis
    for (int a = 0; a < 3; ++a) {
        const float d = ray.dir[a];
        const float x = d == 0.0f ? ray.origin[a] : ray.origin[a] + box.t_enter * d;
        cell[a] = locate(a, x, d);
        step[a] = d > 0.0f ? 1 : (d < 0.0f ? -1 : 0);
        if (step[a] == 0) {
            t_next[a] = kInfinity;  // never crosses a boundary on this axis
        } else {
            const float t = (planes[a][cell[a] + (step[a] > 0 ? 1 : 0)] - ray.origin[a]) * pre.dir_inv[a];
            t_next[a] = t == t ? t : 0.0f;  // NaN: a subnormal d at a plane; it crosses now
        }
    }

    float t_in = box.t_enter;
    // Every step moves one axis' index monotonically, so nx + ny + nz steps
    // leave the grid: the bound guards against any loop rounding might cause.
    const int max_steps = res[0] + res[1] + res[2] + 1;
    for (int steps = 0; steps < max_steps; ++steps) {
        // The axis whose boundary comes first (ties: the lower axis; the other
        // axis follows with a zero-length cell, so no cell is skipped).
        int axis = 0;
        if (t_next[1] < t_next[axis]) axis = 1;
        if (t_next[2] < t_next[axis]) axis = 2;
        float t_out = t_next[axis] < t_end ? t_next[axis] : t_end;
        if (t_out < t_in) t_out = t_in;  // the first cell, when rounding put the entry point past its boundary

        const uint32_t id = cell_id(cell[0], cell[1], cell[2]);
        obs.on({.kind = EventKind::EnterCell, .node = id, .cell = {cell[0], cell[1], cell[2]}, .t_enter = t_in,
                .t_exit = t_out});
        hits.enter(t_out, obs);
        for (uint32_t r = cell_start[id]; r < cell_start[id + 1] && !hits.found_any(); ++r) {
            const uint32_t tri = tri_ids[r];
            hits.test(tri, tri, obs);
        }
        if (hits.can_stop() || !(t_out < t_end)) break;
        cell[axis] += step[axis];
        if (cell[axis] < 0 || cell[axis] >= res[axis]) break;
        t_in = t_out;
        const float t = (planes[axis][cell[axis] + (step[axis] > 0 ? 1 : 0)] - ray.origin[axis]) * pre.dir_inv[axis];
        t_next[axis] = t == t ? t : t_in;
    }
    return hits.done(obs);
}

}  // namespace accelviz
