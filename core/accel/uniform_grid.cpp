#include "core/accel/uniform_grid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "core/geometry/triangle_box.h"

namespace accelviz {

std::string_view to_string(GridInsert insert) { return insert == GridInsert::Box ? "box" : "exact"; }

std::optional<GridInsert> parse_grid_insert(std::string_view name) {
    if (name == "box") return GridInsert::Box;
    if (name == "exact") return GridInsert::Exact;
    return std::nullopt;
}

const std::vector<std::string>& grid_insert_names() {
    static const std::vector<std::string> names = {"box", "exact"};
    return names;
}

std::optional<Error> validate(const GridConfig& c) {
    if (!(c.density > 0.0f) || !std::isfinite(c.density))
        return Error{"--grid-density must be a positive number (the lecture's C ≈ 27)"};
    if (c.max_cells_per_axis < 1 || c.max_cells_per_axis > 4096)
        return Error{"--grid-max-cells-per-axis must be in 1..4096"};
    if (c.max_cells < 1 || c.max_cells > (uint64_t(1) << 30)) return Error{"grid max_cells must be in 1..2^30"};
    if (c.max_references < 1 || c.max_references > 0xffffffffull)
        return Error{"grid max_references must be in 1..2^32-1"};
    return std::nullopt;
}

int UniformGrid::locate(int axis, float x, float d) const {
    const std::vector<float>& p = planes[axis];
    const int n = res[axis];
    // First cell whose upper plane lies above x (or, moving down, at or above x).
    int i = int(std::upper_bound(p.begin() + 1, p.end() - 1, x) - (p.begin() + 1));
    if (d < 0.0f) i = int(std::lower_bound(p.begin() + 1, p.end() - 1, x) - (p.begin() + 1));
    return std::clamp(i, 0, n - 1);
}

namespace {

/// The lecture's rule, #cells ≈ C·N with cells as cubic as the box allows, then
/// the caps. Returns the resolution and appends a note for every cap that applied.
std::array<int, 3> choose_resolution(Vec3 extent, uint32_t triangles, const GridConfig& c,
                                     std::vector<std::string>& notes) {
    std::array<int, 3> res{1, 1, 1};
    const double target = double(c.density) * triangles;
    // Cubic cells of side s over the axes with extent: Π(e_a / s) = target.
    // Axes that would get fewer than one cell are fixed at one and s is solved again
    // for the rest; only then are axes that would get more than max_cells_per_axis
    // fixed at that cap (and s solved again). Without the first rule a thin axis,
    // 1e-7 across in a scene 2e12 long, shrank s so far that the other axes were
    // capped: a million cells for 5 triangles.
    bool capped[3] = {false, false, false};
    bool one_cell[3] = {false, false, false};
    for (int a = 0; a < 3; ++a) one_cell[a] = !(extent[a] > 0.0f);  // zero extent: one cell
    for (int round = 0; round < 4; ++round) {
        double volume = 1, fixed = 1;
        int free_axes = 0;
        for (int a = 0; a < 3; ++a) {
            if (one_cell[a]) continue;
            if (capped[a]) fixed *= c.max_cells_per_axis;
            else { volume *= extent[a]; ++free_axes; }
        }
        for (int a = 0; a < 3; ++a) res[a] = one_cell[a] ? 1 : capped[a] ? c.max_cells_per_axis : res[a];
        if (free_axes == 0) break;
        const double side = std::pow(volume * fixed / std::max(target, 1.0), 1.0 / free_axes);
        double n[3] = {1, 1, 1};
        bool below_one = false;
        for (int a = 0; a < 3; ++a) {
            if (one_cell[a] || capped[a]) continue;
            n[a] = std::round(extent[a] / side);
            if (n[a] < 1.0) one_cell[a] = below_one = true;
        }
        if (below_one) continue;
        bool new_cap = false;
        for (int a = 0; a < 3; ++a) {
            if (one_cell[a] || capped[a]) continue;
            if (n[a] > c.max_cells_per_axis) capped[a] = new_cap = true;
            res[a] = int(std::min<double>(n[a], c.max_cells_per_axis));
        }
        if (!new_cap) break;
    }
    for (int a = 0; a < 3; ++a)
        if (capped[a]) {
            std::ostringstream s;
            s << "axis " << "xyz"[a] << " capped at max_cells_per_axis = " << c.max_cells_per_axis
              << " (the lecture's rule asked for more cubic cells along it; the other axes got more cells instead)";
            notes.push_back(s.str());
        }
    // The total cap: shrink every axis by the same factor.
    const uint64_t total = uint64_t(res[0]) * res[1] * res[2];
    if (total > c.max_cells) {
        const double f = std::cbrt(double(c.max_cells) / double(total));
        for (int a = 0; a < 3; ++a) res[a] = std::max(1, int(std::floor(res[a] * f)));
        std::ostringstream s;
        s << "total cells capped at max_cells = " << c.max_cells << ": the lecture's rule asked for " << total
          << " cells (" << c.density << " x " << triangles << " triangles), the grid has "
          << uint64_t(res[0]) * res[1] * res[2] << " — coarser than the rule";
        notes.push_back(s.str());
    }
    return res;
}

}  // namespace

Expected<UniformGrid> build_uniform_grid(const Mesh& mesh, const GridConfig& config) {
    const auto start = std::chrono::steady_clock::now();
    if (auto err = validate(config)) return *err;
    UniformGrid g;
    g.build_config = config;
    g.triangles = make_triangles(mesh);
    GridBuildStats& st = g.build_stats;
    st.triangles = uint32_t(mesh.triangle_count());
    st.requested_cells = uint64_t(std::llround(double(config.density) * st.triangles));
    if (st.triangles == 0) {
        st.notes.push_back("empty scene: no cells");
        st.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        return g;
    }

    const Aabb scene = mesh.bounds();
    const float pad = reference_padding(scene);
    st.padding = pad;
    g.bounds = padded(scene, pad);
    g.res = choose_resolution(scene.extent(), st.triangles, config, st.notes);
    for (int a = 0; a < 3; ++a) {
        // Boundaries computed once, in double, and shared by build and walk.
        const int n = g.res[a];
        g.planes[a].resize(size_t(n) + 1);
        const double lo = g.bounds.lo[a], hi = g.bounds.hi[a];
        for (int i = 0; i <= n; ++i) g.planes[a][size_t(i)] = float(lo + (hi - lo) * i / n);
        g.planes[a][0] = g.bounds.lo[a];
        g.planes[a][size_t(n)] = g.bounds.hi[a];
    }
    const uint64_t cells = uint64_t(g.res[0]) * g.res[1] * g.res[2];
    st.cells_per_axis = g.res;
    st.cells = cells;

    // Pass 1: the cells of each triangle, triangle by triangle, counted per cell in
    // cell_start (which pass 2 turns into the lists' starts). The lecture's 27 N cells
    // are mostly empty: one array of cells + 1 is all the build gives them.
    g.cell_start.assign(cells + 1, 0);
    std::vector<uint32_t, LargeArrayAllocator<uint32_t>> pairs_cell;  // cell of each reference, triangle by triangle
    pairs_cell.reserve(size_t(st.triangles) * 4);  // a triangle meets about 4 of the rule's cells
    std::vector<uint32_t, LargeArrayAllocator<uint32_t>> pairs_first(size_t(st.triangles) + 1, 0);
    for (uint32_t t = 0; t < st.triangles; ++t) {
        pairs_first[t] = uint32_t(pairs_cell.size());
        const Aabb box = padded(mesh.triangle_bounds(t), pad);
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            // Cells [lo, hi] whose closed extent meets the padded triangle box.
            const auto& p = g.planes[a];
            lo[a] = std::clamp(int(std::lower_bound(p.begin() + 1, p.end(), box.lo[a]) - (p.begin() + 1)), 0,
                               g.res[a] - 1);
            hi[a] = std::clamp(int(std::upper_bound(p.begin(), p.end() - 1, box.hi[a]) - p.begin()) - 1, 0,
                               g.res[a] - 1);
        }
        const Vec3 p0 = mesh.vertex(t, 0), p1 = mesh.vertex(t, 1), p2 = mesh.vertex(t, 2);
        for (int k = lo[2]; k <= hi[2]; ++k)
            for (int j = lo[1]; j <= hi[1]; ++j)
                for (int i = lo[0]; i <= hi[0]; ++i) {
                    if (config.insert == GridInsert::Exact &&
                        !triangle_overlaps_box(p0, p1, p2, padded(g.cell_bounds(i, j, k), pad)))
                        continue;
                    const uint32_t id = g.cell_id(i, j, k);
                    pairs_cell.push_back(id);
                    ++g.cell_start[id];
                }
        if (pairs_cell.size() > config.max_references) {
            std::ostringstream s;
            s << "grid needs more than " << config.max_references << " references (" << cells
              << " cells); lower --grid-density or use --grid-insert exact";
            return Error{s.str()};
        }
    }
    pairs_first[st.triangles] = uint32_t(pairs_cell.size());

    // Pass 2, a counting sort by cell: as inclusive prefix sums the counts say where
    // each cell's list ends; filling the lists back to front, last triangle first,
    // moves each entry to where its list starts, and leaves every list in increasing
    // id order (deterministic, and easy to read in the stepper).
    for (uint64_t c = 1; c < cells; ++c) g.cell_start[c] += g.cell_start[c - 1];
    g.cell_start[cells] = uint32_t(pairs_cell.size());
    g.tri_ids.resize(pairs_cell.size());
    for (uint32_t t = st.triangles; t-- > 0;)
        for (uint32_t r = pairs_first[t + 1]; r-- > pairs_first[t];) g.tri_ids[--g.cell_start[pairs_cell[r]]] = t;

    st.references = g.tri_ids.size();
    for (uint64_t c = 0; c < cells; ++c) {
        const uint32_t count = g.cell_start[c + 1] - g.cell_start[c];
        st.max_per_cell = std::max(st.max_per_cell, count);
        if (count == 0) ++st.empty_cells;
    }
    st.mean_per_cell = double(st.references) / double(cells);
    st.mean_per_nonempty_cell =
        st.empty_cells == cells ? 0.0 : double(st.references) / double(cells - st.empty_cells);
    st.memory_bytes = g.cell_start.size() * sizeof(uint32_t) + g.tri_ids.size() * sizeof(uint32_t) +
                      g.triangles.size() * sizeof(Triangle) +
                      (g.planes[0].size() + g.planes[1].size() + g.planes[2].size()) * sizeof(float);
    st.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return g;
}

bool UniformGrid::intersect_any(const Ray& ray) const {
    // Any hit is a hit: the closest-hit walk answers it (it stops early on the first cell with a hit).
    NoObserver none;
    return intersect_closest(ray, none).found();
}

nlohmann::json UniformGrid::config() const {
    return {{"density", build_config.density},
            {"insert", std::string(to_string(build_config.insert))},
            {"mailbox", build_config.mailbox},
            {"max_cells_per_axis", build_config.max_cells_per_axis},
            {"max_cells", build_config.max_cells}};
}

nlohmann::json UniformGrid::stats() const {
    const GridBuildStats& s = build_stats;
    return {{"triangles", s.triangles},
            {"cells_per_axis", s.cells_per_axis},
            {"cells", s.cells},
            {"requested_cells", s.requested_cells},
            {"empty_cells", s.empty_cells},
            {"empty_percent", s.cells ? 100.0 * double(s.empty_cells) / double(s.cells) : 0.0},
            {"references", s.references},
            {"max_triangles_per_cell", s.max_per_cell},
            {"mean_triangles_per_cell", s.mean_per_cell},
            {"mean_triangles_per_nonempty_cell", s.mean_per_nonempty_cell},
            {"padding", s.padding},
            {"memory_bytes", s.memory_bytes},
            {"build_ms", s.build_ms},
            {"notes", s.notes}};
}

}  // namespace accelviz
