#include "app/gui/structure_overlay.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/accel/bvh.h"
#include "core/accel/kd_tree.h"
#include "core/accel/bsp_tree.h"
#include "core/accel/octree.h"
#include "core/accel/uniform_grid.h"
#include "core/accel/wide_bvh.h"
#include "core/render/colormap.h"

namespace accelviz {

namespace {

/// Colour for position x in [0, 1] of a range; the map's darkest fifth is skipped
/// so the shallowest level stays visible on the dark background.
Rgba8 level_colour(double x, uint8_t alpha = 255) {
    const Rgb c = colormap(0.2 + 0.8 * std::clamp(x, 0.0, 1.0));
    return {c.r, c.g, c.b, alpha};
}

/// Where level `depth` sits in the levels shown [lo, hi].
double level_position(int depth, int lo, int hi) { return hi > lo ? double(depth - lo) / double(hi - lo) : 1.0; }

/// The levels the settings show, clipped to what the structure has.
struct LevelRange {
    int lo, hi;
    bool contains(int depth) const { return depth >= lo && depth <= hi; }
};
/// The levels asked for, clipped to the structure's, and cut short where the
/// boxes of levels lo..hi would pass the budget (`per_level[d]`: boxes level d
/// would add). At least level lo is always shown.
struct ShownLevels {
    LevelRange range;
    bool cut_by_budget = false;
};
ShownLevels shown_levels(const OverlaySettings& s, int deepest, const std::vector<size_t>& per_level) {
    const int lo = std::clamp(s.level_min, 0, deepest);
    ShownLevels shown{{lo, std::clamp(std::max(s.level_max, lo), lo, deepest)}};
    if (s.max_boxes == 0) return shown;
    size_t total = 0;
    for (int d = lo; d <= shown.range.hi; ++d) {
        total += d < int(per_level.size()) ? per_level[size_t(d)] : 0;
        if (total > s.max_boxes && d > lo) {
            shown.range.hi = d - 1;
            shown.cut_by_budget = true;
            break;
        }
    }
    return shown;
}

std::string range_legend(const char* what, ShownLevels shown, int deepest, size_t budget) {
    char text[256];
    std::snprintf(text, sizeof text, "%s: levels %d..%d of 0..%d, colour = depth (blue shallow, yellow deep)", what,
                  shown.range.lo, shown.range.hi, deepest);
    std::string legend = text;
    if (shown.cut_by_budget) {
        std::snprintf(text, sizeof text, "; deeper levels hidden (over %zu boxes: raise the budget or pick levels)",
                      budget);
        legend += text;
    }
    return legend;
}

/// Adds one box at `depth` to the per-level counts.
void count_level(std::vector<size_t>& per_level, int depth) {
    if (per_level.size() <= size_t(depth)) per_level.resize(size_t(depth) + 1, 0);
    ++per_level[size_t(depth)];
}

// [SECTION] Boxes in level order

/// Collects boxes (and a KD tree's planes) with their levels, then lays them out
/// level by level (a stable counting sort: the structure's order within a level)
/// with the levels' ends.
class LevelOrderedBoxes {
public:
    explicit LevelOrderedBoxes(LevelRange levels) : levels_(levels) {}
    void add(const BoxInstance& box, int level) { boxes_.push_back({box, level - levels_.lo}); }
    void add(const ColouredQuad& quad, int level) { quads_.push_back({quad, level - levels_.lo}); }
    void finish(StructureOverlay& out) {
        out.level_ends = order(boxes_, out.boxes);
        out.quad_level_ends = order(quads_, out.quads);
    }

private:
    template <class T>
    struct Pending {
        T item;
        int level;
    };
    template <class T>
    std::vector<size_t> order(const std::vector<Pending<T>>& pending, std::vector<T>& out) const {
        std::vector<size_t> ends(size_t(levels_.hi - levels_.lo + 1), 0);
        for (const Pending<T>& p : pending) ++ends[size_t(p.level)];
        for (size_t k = 1; k < ends.size(); ++k) ends[k] += ends[k - 1];
        std::vector<size_t> next(ends.size(), 0);
        for (size_t k = 1; k < ends.size(); ++k) next[k] = ends[k - 1];
        out.resize(pending.size());
        for (const Pending<T>& p : pending) out[next[size_t(p.level)]++] = p.item;
        return ends;
    }
    LevelRange levels_;
    std::vector<Pending<BoxInstance>> boxes_;
    std::vector<Pending<ColouredQuad>> quads_;
};

// [SECTION] BVH: node boxes by depth

void bvh_overlay(const Bvh& bvh, const OverlaySettings& s, StructureOverlay& out) {
    if (bvh.nodes.empty()) return;
    // Depth of every node, in one pass over the flat array (children follow their parent).
    std::vector<int> depth(bvh.nodes.size(), 0);
    for (size_t i = 0; i < bvh.nodes.size(); ++i) {
        const BvhNode& n = bvh.nodes[i];
        if (!n.is_leaf()) depth[n.first] = depth[n.first + 1] = depth[i] + 1;
        out.deepest_level = std::max(out.deepest_level, depth[i]);
    }
    std::vector<size_t> per_level;
    for (size_t i = 0; i < bvh.nodes.size(); ++i)
        if (!s.leaves_only || bvh.nodes[i].is_leaf()) count_level(per_level, depth[i]);
    const ShownLevels shown = shown_levels(s, out.deepest_level, per_level);
    const LevelRange levels = shown.range;
    LevelOrderedBoxes boxes(levels);
    for (size_t i = 0; i < bvh.nodes.size(); ++i) {
        const BvhNode& n = bvh.nodes[i];
        if (!levels.contains(depth[i]) || (s.leaves_only && !n.is_leaf())) continue;
        boxes.add({n.bounds.lo, n.bounds.hi, level_colour(level_position(depth[i], levels.lo, levels.hi))}, depth[i]);
    }
    boxes.finish(out);
    out.legend = range_legend(s.leaves_only ? "BVH leaves" : "BVH nodes", shown, out.deepest_level, s.max_boxes);
}

/// A wide BVH's boxes by depth: each level is a node's 4 or 8 children, so the tree
/// has about half (4-wide) or a third (8-wide) of the binary tree's levels.
template <class Wide>
void wide_bvh_overlay(const Wide& bvh, const OverlaySettings& s, StructureOverlay& out) {
    std::vector<size_t> per_level;
    bvh.for_each_box([&](uint32_t, const Aabb&, uint32_t depth, uint32_t leaf_count) {
        out.deepest_level = std::max(out.deepest_level, int(depth));
        if (!s.leaves_only || leaf_count > 0) count_level(per_level, int(depth));
    });
    const ShownLevels shown = shown_levels(s, out.deepest_level, per_level);
    const LevelRange levels = shown.range;
    LevelOrderedBoxes boxes(levels);
    bvh.for_each_box([&](uint32_t, const Aabb& box, uint32_t depth, uint32_t leaf_count) {
        if (!levels.contains(int(depth)) || (s.leaves_only && leaf_count == 0)) return;
        boxes.add({box.lo, box.hi, level_colour(level_position(int(depth), levels.lo, levels.hi))}, int(depth));
    });
    boxes.finish(out);
    char what[64];
    std::snprintf(what, sizeof what, "%d-wide BVH %s", Wide::kWidth, s.leaves_only ? "leaves" : "nodes");
    out.legend = range_legend(what, shown, out.deepest_level, s.max_boxes);
    char levels_note[128];
    std::snprintf(levels_note, sizeof levels_note, "; %d levels below the root where the binary tree has %u",
                  out.deepest_level, bvh.binary_stats.max_depth);
    out.legend += levels_note;
}

// [SECTION] Space-partitioning trees: nodes with their depths

struct Cell {
    uint32_t node;
    int depth;
};

/// Every node of a tree from the root (node 0) with its depth, depth first;
/// children(node, push) pushes a node's children (the last pushed comes out first).
/// `deepest` grows to the deepest depth met.
template <class Children>
std::vector<Cell> cells_depth_first(Children&& children, int& deepest) {
    std::vector<Cell> cells;
    std::vector<Cell> stack = {{0, 0}};
    while (!stack.empty()) {
        const Cell c = stack.back();
        stack.pop_back();
        cells.push_back(c);
        deepest = std::max(deepest, c.depth);
        children(c.node, [&](uint32_t child) { stack.push_back({child, c.depth + 1}); });
    }
    return cells;
}

// [SECTION] Octree: cells by depth

void octree_overlay(const Octree& tree, const OverlaySettings& s, StructureOverlay& out) {
    if (tree.nodes.empty()) return;
    const std::vector<Aabb> boxes = tree.node_boxes();
    const std::vector<Cell> cells = cells_depth_first(
        [&](uint32_t node, auto push) {
            const OctreeNode& n = tree.nodes[node];
            if (!n.is_leaf())
                for (int o = 7; o >= 0; --o) push(n.first + uint32_t(o));
        },
        out.deepest_level);
    std::vector<size_t> per_level;
    for (const Cell& c : cells) {
        const OctreeNode& n = tree.nodes[c.node];
        if (!s.leaves_only || (n.is_leaf() && n.count > 0)) count_level(per_level, c.depth);
    }
    const ShownLevels shown = shown_levels(s, out.deepest_level, per_level);
    const LevelRange levels = shown.range;
    LevelOrderedBoxes ordered(levels);
    for (const Cell& c : cells) {
        const OctreeNode& n = tree.nodes[c.node];
        if (!levels.contains(c.depth)) continue;
        if (s.leaves_only && (!n.is_leaf() || n.count == 0)) continue;
        const Aabb& box = boxes[c.node];
        ordered.add({box.lo, box.hi, level_colour(level_position(c.depth, levels.lo, levels.hi))}, c.depth);
    }
    ordered.finish(out);
    out.legend = range_legend(s.leaves_only ? "Octree non-empty leaves" : "Octree cells", shown, out.deepest_level,
                              s.max_boxes);
}

// [SECTION] KD tree: split planes clipped to their node

void kd_overlay(const KdTree& tree, const OverlaySettings& s, StructureOverlay& out) {
    if (tree.nodes.empty()) return;
    const std::vector<Aabb> boxes = tree.node_boxes();
    const std::vector<Cell> cells = cells_depth_first(
        [&](uint32_t node, auto push) {
            const KdNode& n = tree.nodes[node];
            if (n.is_leaf()) return;
            push(n.upper_child());
            push(n.lower_child());
        },
        out.deepest_level);
    std::vector<size_t> per_level;  // one box (a leaf, or a plane's outline) per counted node
    for (const Cell& c : cells) {
        const KdNode& n = tree.nodes[c.node];
        if (s.leaves_only ? (n.is_leaf() && n.count() > 0) : !n.is_leaf()) count_level(per_level, c.depth);
    }
    const ShownLevels shown = shown_levels(s, out.deepest_level, per_level);
    const LevelRange levels = shown.range;
    LevelOrderedBoxes ordered(levels);
    for (const Cell& c : cells) {
        const KdNode& n = tree.nodes[c.node];
        if (!levels.contains(c.depth)) continue;
        const double x = level_position(c.depth, levels.lo, levels.hi);
        const Aabb& box = boxes[c.node];
        if (s.leaves_only) {
            if (n.is_leaf() && n.count() > 0) ordered.add({box.lo, box.hi, level_colour(x)}, c.depth);
            continue;
        }
        if (n.is_leaf()) continue;
        // The plane x_axis = split, as a rectangle spanning the node's box.
        ColouredQuad quad;
        const std::array<Vec3, 4> corners = plane_across_box(box, n.axis(), n.split());
        std::copy(corners.begin(), corners.end(), quad.corners);
        quad.colour = level_colour(x, 70);
        ordered.add(quad, c.depth);
        // The rectangle's outline, so the plane reads edge-on too: a flat box.
        Aabb rim = box;
        rim.lo[n.axis()] = rim.hi[n.axis()] = n.split();
        ordered.add({rim.lo, rim.hi, level_colour(x, 200)}, c.depth);
    }
    ordered.finish(out);
    out.legend = range_legend(s.leaves_only ? "KD non-empty leaves" : "KD split planes", shown, out.deepest_level,
                              s.max_boxes);
}

// [SECTION] BSP tree: its planes inside their cells by depth

constexpr Rgba8 kTrianglePlaneOrange{255, 150, 40, 170};

void bsp_overlay(const BspTree& tree, const OverlaySettings& s, StructureOverlay& out) {
    if (tree.nodes.empty()) return;
    const BspTree::NodeShapes& shapes = tree.node_shapes();
    const std::vector<Cell> cells = cells_depth_first(
        [&](uint32_t node, auto push) {
            const BspNode& n = tree.nodes[node];
            if (n.is_leaf()) return;
            push(n.first + 1);
            push(n.first);
        },
        out.deepest_level);
    std::vector<size_t> per_level;  // a plane's quads, or one leaf's cell bounds, per counted node
    for (const Cell& c : cells) {
        const BspNode& n = tree.nodes[c.node];
        if (s.leaves_only) {
            if (n.is_leaf() && n.count > 0) count_level(per_level, c.depth);
        } else {
            for (size_t q = 2; q < shapes.split_polygons[c.node].size(); ++q) count_level(per_level, c.depth);
        }
    }
    const ShownLevels shown = shown_levels(s, out.deepest_level, per_level);
    const LevelRange levels = shown.range;
    LevelOrderedBoxes ordered(levels);
    for (const Cell& c : cells) {
        const BspNode& n = tree.nodes[c.node];
        if (!levels.contains(c.depth)) continue;
        const double x = level_position(c.depth, levels.lo, levels.hi);
        if (s.leaves_only) {
            const Aabb& box = shapes.cell_bounds[c.node];
            if (n.is_leaf() && n.count > 0 && !box.empty()) ordered.add({box.lo, box.hi, level_colour(x)}, c.depth);
            continue;
        }
        // The plane inside the node's cell, a convex polygon, as a fan of quads
        // (a triangle is a quad with its last corner twice). A triangle's own plane
        // stands out in orange: what a BSP tree has and a KD tree has not.
        const Polygon& poly = shapes.split_polygons[c.node];
        for (size_t i = 1; i + 1 < poly.size(); ++i) {
            ColouredQuad quad;
            quad.corners[0] = poly[0];
            quad.corners[1] = poly[i];
            quad.corners[2] = quad.corners[3] = poly[i + 1];
            quad.colour = n.from_triangle ? kTrianglePlaneOrange : level_colour(x, 60);
            ordered.add(quad, c.depth);
        }
    }
    ordered.finish(out);
    if (s.leaves_only) {
        out.legend = range_legend("BSP non-empty leaves (their cells' bounds)", shown, out.deepest_level, s.max_boxes);
        return;
    }
    char what[96];
    std::snprintf(what, sizeof what, "BSP planes (orange: %u of %u are triangles' planes; the rest axis-aligned)",
                  tree.build_stats.triangle_planes, tree.build_stats.triangle_planes + tree.build_stats.axis_planes);
    out.legend = range_legend(what, shown, out.deepest_level, s.max_boxes);
}

// [SECTION] Grid: non-empty cells by triangle count

void grid_overlay(const UniformGrid& grid, StructureOverlay& out) {
    uint32_t most = 0;
    for (size_t c = 0; c + 1 < grid.cell_start.size(); ++c) most = std::max(most, grid.cell_start[c + 1] - grid.cell_start[c]);
    if (most == 0) return;
    for (int k = 0; k < grid.res[2]; ++k)
        for (int j = 0; j < grid.res[1]; ++j)
            for (int i = 0; i < grid.res[0]; ++i) {
                const uint32_t id = grid.cell_id(i, j, k);
                const uint32_t count = grid.cell_start[id + 1] - grid.cell_start[id];
                if (count == 0) continue;
                const Aabb box = grid.cell_bounds(i, j, k);
                out.boxes.push_back({box.lo, box.hi, level_colour(most > 1 ? double(count - 1) / (most - 1) : 1.0)});
            }
    char text[160];
    std::snprintf(text, sizeof text, "Grid %dx%dx%d: %zu non-empty cells, colour = triangles in the cell (1..%u)",
                  grid.res[0], grid.res[1], grid.res[2], out.boxes.size(), most);
    out.legend = text;
}

// [SECTION] A structure file that is not valid: its own nodes, the faulty ones red

/// The other boxes, faint, so that the red ones stand out.
constexpr uint8_t kFaintAlpha = 80;

/// Depth of every node reached from the root, each once (-1: not reached), following
/// only child indices in range: safe on a file with cycles or shared nodes.
template <class Children>
std::vector<int> file_depths(size_t count, Children&& children, int& deepest) {
    std::vector<int> depth(count, -1);
    if (count == 0) return depth;
    depth[0] = 0;
    std::vector<uint32_t> queue = {0};
    for (size_t q = 0; q < queue.size(); ++q) {
        const uint32_t n = queue[q];
        for (uint32_t c : children(n)) {
            if (c >= count || depth[c] >= 0) continue;
            depth[c] = depth[n] + 1;
            deepest = std::max(deepest, depth[c]);
            queue.push_back(c);
        }
    }
    return depth;
}

void file_overlay(const StructureFile& f, const StructureCheck& check, const OverlaySettings& s,
                  StructureOverlay& out) {
    auto bad = [&](uint64_t i) { return std::binary_search(check.bad_nodes.begin(), check.bad_nodes.end(), i); };
    if (f.type == AccelType::Grid) {
        // Listed cells, the faulty entries red: a grid has no levels.
        const Vec3 e = f.bounds.extent();
        const float nx = float(std::max(f.resolution[0], 1u)), ny = float(std::max(f.resolution[1], 1u)),
                    nz = float(std::max(f.resolution[2], 1u));
        const Vec3 size{e.x / nx, e.y / ny, e.z / nz};
        size_t most = 1;
        for (const FileGridCell& c : f.cells) most = std::max(most, c.triangles.size());
        for (size_t i = 0; i < f.cells.size(); ++i) {
            const FileGridCell& c = f.cells[i];
            const Vec3 lo{f.bounds.lo.x + size.x * float(c.cell[0]), f.bounds.lo.y + size.y * float(c.cell[1]),
                          f.bounds.lo.z + size.z * float(c.cell[2])};
            const Aabb box{lo, {lo.x + size.x, lo.y + size.y, lo.z + size.z}};
            if (!finite_box(box)) continue;
            const bool fault = bad(i);
            if (!fault && c.triangles.empty()) continue;
            out.boxes.push_back({box.lo, box.hi, fault ? kFaultRed : level_colour(double(c.triangles.size()) / double(most), kFaintAlpha)});
        }
        return;
    }
    const bool is_bvh = f.type == AccelType::Bvh;
    const size_t count = is_bvh ? f.bvh_nodes.size() : f.kd_nodes.size();
    const std::vector<int> depth = file_depths(
        count,
        [&](uint32_t n) {
            if (is_bvh) return f.bvh_nodes[n].children;
            const FileKdNode& k = f.kd_nodes[n];
            return k.is_leaf() ? std::vector<uint32_t>{} : std::vector<uint32_t>{k.children[0], k.children[1]};
        },
        out.deepest_level);
    const std::vector<Aabb> kd_cell = is_bvh ? std::vector<Aabb>{} : file_kd_cells(f);
    auto box_of = [&](size_t i) { return is_bvh ? f.bvh_nodes[i].box : kd_cell[i]; };
    auto leaf = [&](size_t i) { return is_bvh ? !f.bvh_nodes[i].interior : f.kd_nodes[i].is_leaf(); };
    std::vector<size_t> per_level;
    for (size_t i = 0; i < count; ++i)
        if (depth[i] >= 0 && (!s.leaves_only || leaf(i))) count_level(per_level, depth[i]);
    const ShownLevels shown = shown_levels(s, out.deepest_level, per_level);
    const LevelRange levels = shown.range;
    LevelOrderedBoxes ordered(levels);
    for (size_t i = 0; i < count; ++i) {
        const Aabb box = box_of(i);
        if (!finite_box(box)) continue;
        if (bad(i)) {  // always drawn, with the first level shown (so a moving camera keeps it too)
            ordered.add({box.lo, box.hi, kFaultRed}, levels.lo);
            continue;
        }
        if (depth[i] < 0 || !levels.contains(depth[i]) || (s.leaves_only && !leaf(i))) continue;
        const double x = level_position(depth[i], levels.lo, levels.hi);
        if (is_bvh || s.leaves_only) {
            ordered.add({box.lo, box.hi, level_colour(x, kFaintAlpha)}, depth[i]);
            continue;
        }
        const FileKdNode& n = f.kd_nodes[i];
        if (n.is_leaf() || !(n.split >= box.lo[n.axis] && n.split <= box.hi[n.axis])) continue;
        ColouredQuad quad;
        const std::array<Vec3, 4> corners = plane_across_box(box, n.axis, n.split);
        std::copy(corners.begin(), corners.end(), quad.corners);
        quad.colour = level_colour(x, 70);
        ordered.add(quad, depth[i]);
    }
    ordered.finish(out);
}

}  // namespace

uint64_t LeafHistogram::total() const {
    uint64_t sum = 0;
    for (uint64_t c : counts) sum += c;
    return sum;
}

LeafHistogram leaf_histogram(const Accelerator& accel) {
    LeafHistogram out;
    auto add = [&out](uint64_t triangles) {
        if (out.counts.size() <= triangles) out.counts.resize(triangles + 1, 0);
        ++out.counts[triangles];
    };
    auto add_wide_leaves = [&](const auto& wide) {
        out.what = "BVH leaves";
        wide.for_each_box([&](uint32_t, const Aabb&, uint32_t, uint32_t leaf_count) {
            if (leaf_count > 0) add(leaf_count);
        });
    };
    if (const Bvh* bvh = structure_if<Bvh>(accel)) {
        out.what = "BVH leaves";
        for (const BvhNode& n : bvh->nodes)
            if (n.is_leaf()) add(n.count);
    } else if (const auto* wide4 = structure_if<WideBvh<4>>(accel)) {
        add_wide_leaves(*wide4);
    } else if (const auto* wide8 = structure_if<WideBvh<8>>(accel)) {
        add_wide_leaves(*wide8);
    } else if (const Octree* octree = structure_if<Octree>(accel)) {
        out.what = "octree leaves";
        for (const OctreeNode& n : octree->nodes)
            if (n.is_leaf()) add(n.count);
    } else if (const KdTree* kd = structure_if<KdTree>(accel)) {
        out.what = "KD leaves";
        for (const KdNode& n : kd->nodes)
            if (n.is_leaf()) add(n.count());
    } else if (const BspTree* bsp = structure_if<BspTree>(accel)) {
        out.what = "BSP leaves";
        for (const BspNode& n : bsp->nodes)
            if (n.is_leaf()) add(n.count);
    } else if (const UniformGrid* grid = structure_if<UniformGrid>(accel)) {
        out.what = "grid cells";
        const auto& start = grid->cell_start;
        for (size_t c = 0; c + 1 < start.size(); ++c) add(start[c + 1] - start[c]);
    }
    return out;
}

size_t StructureOverlay::moving_levels(size_t budget) const {
    // The first level with boxes (leaves only: the shallowest leaves), then every
    // further level that keeps the boxes within the budget.
    size_t levels = 0;
    while (levels < level_ends.size() && level_ends[levels] == 0) ++levels;
    if (levels < level_ends.size()) ++levels;
    while (levels < level_ends.size() && level_ends[levels] <= budget) ++levels;
    return levels;
}

size_t StructureOverlay::moving_prefix(size_t budget) const {
    if (level_ends.empty()) return boxes.size();
    const size_t levels = moving_levels(budget);
    return levels == 0 ? 0 : level_ends[levels - 1];
}

size_t StructureOverlay::deeper_prefix(size_t budget) const {
    if (level_ends.empty()) return boxes.size();
    const size_t levels = moving_levels(budget);
    return levels < level_ends.size() ? level_ends[levels] : boxes.size();
}

size_t StructureOverlay::moving_quads(size_t budget) const {
    if (quad_level_ends.empty()) return quads.size();
    const size_t levels = std::min(moving_levels(budget), quad_level_ends.size());
    return levels == 0 ? 0 : quad_level_ends[levels - 1];
}

StructureOverlay make_file_overlay(const StructureFile& file, const StructureCheck& check,
                                   const OverlaySettings& settings) {
    StructureOverlay out;
    file_overlay(file, check, settings, out);
    char text[160];
    std::snprintf(text, sizeof text,
                  "NOT VALID: %llu problem%s (Structure panel); red: the nodes they name. Rays go through brute force",
                  (unsigned long long)check.problem_count, check.problem_count == 1 ? "" : "s");
    out.legend = text;
    return out;
}

StructureOverlay make_structure_overlay(const Accelerator& accel, const OverlaySettings& settings) {
    StructureOverlay out;
    if (const Bvh* bvh = structure_if<Bvh>(accel))
        bvh_overlay(*bvh, settings, out);
    else if (const auto* wide4 = structure_if<WideBvh<4>>(accel))
        wide_bvh_overlay(*wide4, settings, out);
    else if (const auto* wide8 = structure_if<WideBvh<8>>(accel))
        wide_bvh_overlay(*wide8, settings, out);
    else if (const Octree* octree = structure_if<Octree>(accel))
        octree_overlay(*octree, settings, out);
    else if (const KdTree* kd = structure_if<KdTree>(accel))
        kd_overlay(*kd, settings, out);
    else if (const BspTree* bsp = structure_if<BspTree>(accel))
        bsp_overlay(*bsp, settings, out);
    else if (const UniformGrid* grid = structure_if<UniformGrid>(accel))
        grid_overlay(*grid, out);
    else
        out.legend = "naive: no structure, every ray tests every triangle";
    return out;
}

bool finite_box(const Aabb& b) {
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(b.lo[a]) || !std::isfinite(b.hi[a])) return false;
    return true;
}

}  // namespace accelviz
