#include "core/accel/uniform_grid.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <sstream>

#include <tbb/parallel_for.h>

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

/// The cells along one axis whose closed extent meets an interval, as a binary search
/// over the planes would find them, but from the uniform spacing's guess, corrected
/// against the planes themselves (the planes are rounded to float, so the guess can
/// be one off; the loops make the answer exact). Coordinates are finite (load_scene).
class AxisCells {
public:
    AxisCells(const UniformGrid& g, int axis)
        : p_(g.planes[axis].data()), n_(g.res[axis]), lo_(g.bounds.lo[axis]) {
        const double extent = double(g.bounds.hi[axis]) - double(g.bounds.lo[axis]);
        scale_ = extent > 0.0 ? double(n_) / extent : 0.0;
    }
    /// The number of upper planes p[1..n] below `from`, at most n - 1: the first cell.
    int first(float from) const {
        int i = guess(from);
        while (i > 0 && !(p_[i] < from)) --i;
        while (i < n_ && p_[i + 1] < from) ++i;
        return std::min(i, n_ - 1);
    }
    /// The number of lower planes p[0..n-1] at or below `to`, minus one, at least 0: the last cell.
    int last(float to) const {
        int j = guess(to);
        while (j >= 0 && !(p_[j] <= to)) --j;
        while (j < n_ - 1 && p_[j + 1] <= to) ++j;
        return std::max(j, 0);
    }

private:
    int guess(float x) const {
        const double cell = std::floor((double(x) - lo_) * scale_);
        if (!(cell > 0.0)) return 0;  // (also NaN)
        return int(std::min(cell, double(n_ - 1)));
    }
    const float* p_;
    int n_;
    double lo_, scale_ = 0.0;
};

/// Triangles per chunk of the build's parallel first pass.
constexpr uint32_t kTrianglesPerChunk = 8192;

/// One chunk's references: the cells of its triangles, triangle by triangle;
/// triangle first + t has cells[first_of[t] .. first_of[t + 1]).
struct ChunkReferences {
    std::vector<uint32_t> cells;
    std::vector<uint32_t> first_of;
};

}  // namespace

std::vector<float> grid_axis_planes(float lo, float hi, int n) {
    std::vector<float> planes(size_t(n) + 1);
    for (int i = 0; i <= n; ++i) planes[size_t(i)] = float(double(lo) + (double(hi) - double(lo)) * i / n);
    planes.front() = lo;
    planes.back() = hi;
    return planes;
}

Expected<UniformGrid> build_uniform_grid(const Mesh& mesh, const GridConfig& config, WorkProgress* progress) {
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
    for (int a = 0; a < 3; ++a) g.planes[a] = grid_axis_planes(g.bounds.lo[a], g.bounds.hi[a], g.res[a]);
    const uint64_t cells = uint64_t(g.res[0]) * g.res[1] * g.res[2];
    st.cells_per_axis = g.res;
    st.cells = cells;

    // Pass 1: the cells of each triangle, counted per cell in cell_start (which pass 2
    // turns into the lists' starts). The lecture's 27 N cells are mostly empty: one
    // array of cells + 1 is all the build gives them. Chunks of triangles run in
    // parallel, each keeping its references (cells, triangle by triangle) to itself;
    // counts are added atomically (integers: the same sums in any order).
    g.cell_start.assign(cells + 1, 0);
    const uint32_t chunk_count = (st.triangles + kTrianglesPerChunk - 1) / kTrianglesPerChunk;
    std::vector<ChunkReferences> chunks(chunk_count);
    const std::array<AxisCells, 3> axis_cells = {AxisCells(g, 0), AxisCells(g, 1), AxisCells(g, 2)};
    std::atomic<uint64_t> references{0};
    std::atomic<bool> too_many{false};
    start_stage(progress, 2 * uint64_t(chunk_count));  // each chunk once per pass
    tbb::parallel_for(uint32_t(0), chunk_count, [&](uint32_t c) {
        if (cancelled(progress)) return;
        ChunkReferences& chunk = chunks[c];
        const uint32_t first = c * kTrianglesPerChunk, end = std::min(st.triangles, first + kTrianglesPerChunk);
        chunk.first_of.reserve(end - first + 1);
        chunk.cells.reserve(size_t(end - first) * 4);  // a triangle meets about 4 of the rule's cells
        for (uint32_t t = first; t < end && !too_many.load(std::memory_order_relaxed); ++t) {
            chunk.first_of.push_back(uint32_t(chunk.cells.size()));
            const Aabb box = padded(mesh.triangle_bounds(t), pad);
            int lo[3], hi[3];
            for (int a = 0; a < 3; ++a) {
                lo[a] = axis_cells[a].first(box.lo[a]);
                hi[a] = axis_cells[a].last(box.hi[a]);
            }
            const Vec3 p0 = mesh.vertex(t, 0), p1 = mesh.vertex(t, 1), p2 = mesh.vertex(t, 2);
            for (int k = lo[2]; k <= hi[2]; ++k)
                for (int j = lo[1]; j <= hi[1]; ++j)
                    for (int i = lo[0]; i <= hi[0]; ++i) {
                        if (config.insert == GridInsert::Exact &&
                            !triangle_overlaps_box(p0, p1, p2, padded(g.cell_bounds(i, j, k), pad)))
                            continue;
                        const uint32_t id = g.cell_id(i, j, k);
                        chunk.cells.push_back(id);
                        std::atomic_ref<uint32_t>(g.cell_start[id]).fetch_add(1, std::memory_order_relaxed);
                    }
            // Early out (memory): this chunk's references and those of finished chunks are
            // parts of the total, so it is over the limit if they are.
            if (chunk.cells.size() + references.load(std::memory_order_relaxed) > config.max_references)
                too_many = true;
        }
        chunk.first_of.push_back(uint32_t(chunk.cells.size()));
        references += chunk.cells.size();
        advance(progress, 1);
    });
    if (cancelled(progress)) return WorkProgress::cancelled_error();
    if (too_many || references > config.max_references) {
        std::ostringstream s;
        s << "grid needs more than " << config.max_references << " references (" << cells
          << " cells); lower --grid-density or use --grid-insert exact";
        return Error{s.str()};
    }

    // Pass 2, a counting sort by cell: as inclusive prefix sums the counts say where
    // each cell's list ends; filling the lists back to front, last triangle first,
    // moves each entry to where its list starts, and leaves every list in increasing
    // id order (deterministic, and easy to read in the stepper).
    for (uint64_t c = 1; c < cells; ++c) g.cell_start[c] += g.cell_start[c - 1];
    g.cell_start[cells] = uint32_t(references.load());
    g.tri_ids.resize(references.load());
    for (uint32_t c = chunk_count; c-- > 0;) {
        if (cancelled(progress)) return WorkProgress::cancelled_error();
        advance(progress, 1);
        const ChunkReferences& chunk = chunks[c];
        for (uint32_t t = uint32_t(chunk.first_of.size()) - 1; t-- > 0;)
            for (uint32_t r = chunk.first_of[t + 1]; r-- > chunk.first_of[t];)
                g.tri_ids[--g.cell_start[chunk.cells[r]]] = c * kTrianglesPerChunk + t;
    }

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

nlohmann::json UniformGrid::config() const {
    return {{"density", build_config.density},
            {"insert", std::string(to_string(build_config.insert))},
            {"mailbox", build_config.mailbox},
            {"max_cells_per_axis", build_config.max_cells_per_axis},
            {"max_cells", build_config.max_cells},
            {"triangle_test", std::string(to_string(triangle_test))}};
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
