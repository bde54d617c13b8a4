#include "core/exchange/structure_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/accel/bvh.h"
#include "core/accel/kd_tree.h"
#include "core/accel/uniform_grid.h"
#include "core/accel/wide_bvh.h"
#include "core/geometry/triangle_box.h"

namespace accelviz {

float containment_tolerance(const Mesh& mesh) {
    const Aabb b = mesh.bounds();
    if (b.empty()) return 0.0f;
    const Vec3 e = b.extent();
    return 1e-6f * std::max({e.x, e.y, e.z});
}

namespace {

/// Grids with more cells than this, or more along one axis, are refused (the check
/// keeps a table per cell; ours has at most 2^24 cells and 1024 per axis).
constexpr uint64_t kMaxGridCells = uint64_t(1) << 24;
constexpr uint32_t kMaxGridCellsPerAxis = 1u << 16;

std::string number(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", x);
    return buf;
}

/// Collects problems: all counted, the first `max_listed` kept in words.
class Problems {
public:
    Problems(StructureCheck& out, size_t max_listed) : out_(out), max_listed_(max_listed) {}
    void add(std::optional<uint64_t> node, std::string message) {
        ++out_.problem_count;
        if (node) out_.bad_nodes.push_back(*node);
        if (listing()) out_.problems.push_back({node, std::move(message)});
    }
    /// Whether a problem added now is listed in words (else only counted: callers
    /// with many problems skip making their messages).
    bool listing() const { return out_.problems.size() < max_listed_; }
    /// A problem counted (and its node named) without words: the list is full.
    void count(std::optional<uint64_t> node) {
        ++out_.problem_count;
        if (node) out_.bad_nodes.push_back(*node);
    }
    /// Names `node` among the bad ones without a problem of its own (the other party
    /// of a problem: the parent a child's box sticks out of).
    void mark(uint64_t node) { out_.bad_nodes.push_back(node); }
    void finish() {
        std::sort(out_.bad_nodes.begin(), out_.bad_nodes.end());
        out_.bad_nodes.erase(std::unique(out_.bad_nodes.begin(), out_.bad_nodes.end()), out_.bad_nodes.end());
    }

private:
    StructureCheck& out_;
    size_t max_listed_;
};

bool is_box(const Aabb& b) {
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(b.lo[a]) || !std::isfinite(b.hi[a]) || !(b.lo[a] <= b.hi[a])) return false;
    return true;
}

std::string box_words(const Aabb& b) {
    std::ostringstream s;
    s << "[" << number(b.lo.x) << ", " << number(b.lo.y) << ", " << number(b.lo.z) << "] to [" << number(b.hi.x)
      << ", " << number(b.hi.y) << ", " << number(b.hi.z) << "]";
    return s.str();
}

/// How far `inner` sticks out of `outer`, and on which face ("+x", "-z"); 0 when inside.
struct Overhang {
    float amount = 0;
    std::string face;
};
Overhang overhang(const Aabb& inner, const Aabb& outer) {
    Overhang worst;
    const char* axes = "xyz";
    for (int a = 0; a < 3; ++a) {
        const float below = outer.lo[a] - inner.lo[a], above = inner.hi[a] - outer.hi[a];
        if (below > worst.amount) worst = {below, std::string("-") + axes[a]};
        if (above > worst.amount) worst = {above, std::string("+") + axes[a]};
    }
    return worst;
}

void check_mesh(const StructureFile& f, const Mesh& mesh, std::optional<uint32_t> mesh_crc, Problems& problems) {
    if (f.mesh.triangles != mesh.triangle_count())
        problems.add(std::nullopt, "the file is for a mesh of " + std::to_string(f.mesh.triangles) +
                                       " triangles; this mesh has " + std::to_string(mesh.triangle_count()));
    if (f.mesh.crc32 && mesh_crc && *f.mesh.crc32 != *mesh_crc) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "the file names a mesh with CRC-32 %08x; this mesh's is %08x", *f.mesh.crc32,
                      *mesh_crc);
        problems.add(std::nullopt, std::string(buf) + ": another mesh, or the same one changed");
    }
}

/// The tree shape shared by the BVH and the KD tree: every child index in range, each
/// node reached once from the root (no cycle, no second parent), every node reached.
/// Fills depth[] (UINT32_MAX: not reached) and returns the deepest depth.
template <class ChildrenOf>
uint32_t check_tree_shape(size_t node_count, ChildrenOf children_of, std::vector<uint32_t>& depth,
                          std::vector<uint32_t>& parent, Problems& problems) {
    depth.assign(node_count, UINT32_MAX);
    parent.assign(node_count, UINT32_MAX);
    if (node_count == 0) return 0;
    depth[0] = 0;
    uint32_t deepest = 0;
    std::vector<uint32_t> stack = {0};
    while (!stack.empty()) {
        const uint32_t n = stack.back();
        stack.pop_back();
        for (uint32_t c : children_of(n)) {
            if (c >= node_count) {
                problems.add(n, "node " + std::to_string(n) + " names child " + std::to_string(c) +
                                    ", but the file has nodes 0 to " + std::to_string(node_count - 1));
                continue;
            }
            if (depth[c] != UINT32_MAX) {
                // Reached before: a second parent, or a cycle (a node above). Told apart
                // without walking up the tree, which on a long chain named many times over
                // would take quadratic time.
                if (!problems.listing()) {
                    problems.count(n);
                } else if (c == 0 || c == n) {
                    problems.add(n, "node " + std::to_string(n) + " names node " + std::to_string(c) +
                                        " as a child, which is itself or the root: a cycle");
                } else {
                    problems.add(n, "node " + std::to_string(c) + " is reached a second time, from node " +
                                        std::to_string(n) + " (first from node " + std::to_string(parent[c]) +
                                        "): a node has one parent, and no node is its own ancestor");
                }
                continue;
            }
            depth[c] = depth[n] + 1;
            parent[c] = n;
            deepest = std::max(deepest, depth[c]);
            stack.push_back(c);
        }
    }
    uint64_t unreached = 0;
    uint32_t first_unreached = 0;
    for (size_t i = 0; i < node_count; ++i)
        if (depth[i] == UINT32_MAX && unreached++ == 0) first_unreached = uint32_t(i);
    if (unreached > 0)
        problems.add(first_unreached, "node " + std::to_string(first_unreached) + " is not reachable from the root" +
                                          (unreached > 1 ? " (nor are " + std::to_string(unreached - 1) + " more)" : ""));
    return deepest;
}

/// Triangles listed `times[t]` times: those in none and those in several, as two
/// problems each naming the first few.
void check_each_triangle_once(const std::vector<uint32_t>& times, const std::vector<uint64_t>& where_first,
                              Problems& problems) {
    std::vector<uint32_t> missing, twice;
    for (uint32_t t = 0; t < times.size(); ++t) {
        if (times[t] == 0) missing.push_back(t);
        if (times[t] > 1) twice.push_back(t);
    }
    auto first_few = [](const std::vector<uint32_t>& ids) {
        std::string s;
        for (size_t i = 0; i < std::min<size_t>(ids.size(), 8); ++i) s += (i ? ", " : "") + std::to_string(ids[i]);
        return s + (ids.size() > 8 ? ", ..." : "");
    };
    if (!missing.empty())
        problems.add(std::nullopt, std::to_string(missing.size()) + " triangle" + (missing.size() > 1 ? "s are" : " is") +
                                       " in no leaf (" + first_few(missing) + "): rays through them would miss");
    for (uint32_t t : twice) {
        if (!problems.listing()) {
            problems.count(where_first[t]);
            continue;
        }
        problems.add(where_first[t], "triangle " + std::to_string(t) + " is in " + std::to_string(times[t]) +
                                         " leaves (first in node " + std::to_string(where_first[t]) +
                                         "): a BVH holds each triangle once");
    }
}

void check_bvh(const StructureFile& f, const Mesh& mesh, Problems& problems) {
    const auto& nodes = f.bvh_nodes;
    const uint64_t n_tris = mesh.triangle_count();
    if (nodes.empty()) {
        if (n_tris > 0) problems.add(std::nullopt, "no nodes: a BVH over triangles needs at least a root");
        return;
    }
    const float tol = containment_tolerance(mesh);
    for (size_t i = 0; i < nodes.size(); ++i) {
        const FileBvhNode& n = nodes[i];
        const std::string who = "node " + std::to_string(i);
        if (!is_box(n.box)) problems.add(i, who + "'s box " + box_words(n.box) + " is not a box (lo <= hi, finite)");
        if (n.interior && n.children.empty()) problems.add(i, who + " is an empty inner node: no children");
        else if (n.interior && n.children.size() == 1)
            problems.add(i, who + " has one child: an inner node has 2 to " + std::to_string(kStructureMaxArity));
        else if (n.interior && n.children.size() > size_t(kStructureMaxArity))
            problems.add(i, who + " has " + std::to_string(n.children.size()) + " children: at most " +
                                std::to_string(kStructureMaxArity));
        if (!n.interior && n.count == 0) problems.add(i, who + " is a leaf with no triangles");
        if (!n.interior && (n.first > f.order.size() || n.count > f.order.size() - n.first))
            problems.add(i, who + "'s triangles order[" + std::to_string(n.first) + " .. " +
                                std::to_string(n.first) + " + " + std::to_string(n.count) +
                                ") run past the end of \"order\" (" + std::to_string(f.order.size()) + " entries)");
        if (!n.interior && n.count > 0xFFFF)
            problems.add(i, who + " holds " + std::to_string(n.count) + " triangles: at most 65535 per leaf");
    }
    std::vector<uint32_t> depth, parent;
    const uint32_t deepest = check_tree_shape(
        nodes.size(), [&](uint32_t n) -> const std::vector<uint32_t>& { return nodes[n].children; }, depth, parent,
        problems);
    if (deepest > kBvhMaxDepth)
        problems.add(std::nullopt, "the tree is " + std::to_string(deepest) + " levels deep; traversal stacks here hold " +
                                       std::to_string(kBvhMaxDepth) + " (a balanced tree over 2^63 triangles)");
    // Boxes: each child inside its parent; each leaf's triangles inside the leaf.
    std::vector<uint32_t> times(n_tris, 0);
    std::vector<uint64_t> where_first(n_tris, 0);
    std::vector<uint8_t> claimed(f.order.size(), 0);
    for (size_t i = 0; i < nodes.size(); ++i) {
        if (depth[i] == UINT32_MAX) continue;
        const FileBvhNode& n = nodes[i];
        if (parent[i] != UINT32_MAX && is_box(n.box) && is_box(nodes[parent[i]].box)) {
            const Overhang o = overhang(n.box, nodes[parent[i]].box);
            if (o.amount > tol) {
                problems.add(i, "node " + std::to_string(i) + "'s box sticks out of its parent's (node " +
                                    std::to_string(parent[i]) + ") by " + number(o.amount) + " on " + o.face);
                problems.mark(parent[i]);
            }
        }
        if (n.interior || n.first > f.order.size() || n.count > f.order.size() - n.first) continue;
        for (uint64_t k = n.first; k < n.first + n.count; ++k) {
            if (claimed[k]) {  // another leaf's range: each entry of "order" belongs to one leaf
                problems.add(i, "node " + std::to_string(i) + "'s range of \"order\" overlaps another leaf's (at " +
                                    std::to_string(k) + ")");
                break;
            }
            claimed[k] = 1;
            const uint32_t t = f.order[k];
            if (t >= n_tris) {
                problems.add(i, "node " + std::to_string(i) + " holds order[" + std::to_string(k) + "] = " +
                                    std::to_string(t) + ", not a triangle: the mesh has " + std::to_string(n_tris));
                continue;
            }
            if (times[t]++ == 0) where_first[t] = i;
            if (!is_box(n.box)) continue;
            const Overhang o = overhang(mesh.triangle_bounds(t), n.box);
            if (o.amount <= tol) continue;
            if (!problems.listing()) problems.count(i);
            else
                problems.add(i, "triangle " + std::to_string(t) + " sticks out of its leaf's box (node " +
                                    std::to_string(i) + ") by " + number(o.amount) + " on " + o.face);
        }
    }
    check_each_triangle_once(times, where_first, problems);
}

void check_kd(const StructureFile& f, const Mesh& mesh, Problems& problems) {
    const auto& nodes = f.kd_nodes;
    const uint64_t n_tris = mesh.triangle_count();
    const float tol = containment_tolerance(mesh);
    if (!is_box(f.bounds)) {
        problems.add(std::nullopt, "\"bounds\" " + box_words(f.bounds) + " is not a box (lo <= hi, finite)");
        return;
    }
    if (nodes.empty()) {
        if (n_tris > 0) problems.add(std::nullopt, "no nodes: a KD tree over triangles needs at least a root");
        return;
    }
    const Overhang scene = overhang(mesh.bounds(), f.bounds);
    if (scene.amount > tol)
        problems.add(std::nullopt, "the mesh sticks out of \"bounds\" by " + number(scene.amount) + " on " + scene.face);
    std::vector<uint32_t> depth, parent;
    const uint32_t deepest = check_tree_shape(
        nodes.size(),
        [&](uint32_t n) {
            return nodes[n].is_leaf() ? std::vector<uint32_t>{}
                                      : std::vector<uint32_t>{nodes[n].children[0], nodes[n].children[1]};
        },
        depth, parent, problems);
    if (deepest > uint32_t(kKdMaxDepth))
        problems.add(std::nullopt, "the tree is " + std::to_string(deepest) + " levels deep; the KD walk here takes " +
                                       std::to_string(kKdMaxDepth));
    const std::vector<Aabb> cell = file_kd_cells(f);
    for (size_t i = 0; i < nodes.size(); ++i) {
        const FileKdNode& n = nodes[i];
        if (depth[i] == UINT32_MAX || n.is_leaf()) continue;
        if (!std::isfinite(n.split) || !(n.split > cell[i].lo[n.axis] && n.split < cell[i].hi[n.axis]))
            problems.add(i, "node " + std::to_string(i) + " splits " + "xyz"[n.axis] + " at " + number(n.split) +
                                ", not inside its cell (" + number(cell[i].lo[n.axis]) + " to " +
                                number(cell[i].hi[n.axis]) + ")");
    }
    // Every leaf's list, sorted, to look triangles up.
    std::vector<std::vector<uint32_t>> sorted(nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i) {
        if (!nodes[i].is_leaf() || depth[i] == UINT32_MAX) continue;
        sorted[i] = nodes[i].triangles;
        std::sort(sorted[i].begin(), sorted[i].end());
        for (uint32_t t : sorted[i])
            if (t >= n_tris) {
                problems.add(i, "node " + std::to_string(i) + " lists " + std::to_string(t) +
                                    ", not a triangle: the mesh has " + std::to_string(n_tris));
                break;
            }
    }
    // Each triangle down the tree to every leaf cell it overlaps: it must be listed there.
    std::vector<uint32_t> stack;
    for (uint32_t t = 0; t < n_tris; ++t) {
        const Aabb tb = mesh.triangle_bounds(t);
        stack.assign(1, 0u);
        while (!stack.empty()) {
            const uint32_t i = stack.back();
            stack.pop_back();
            if (depth[i] == UINT32_MAX) continue;
            const FileKdNode& n = nodes[i];
            if (!n.is_leaf()) {
                for (int side = 0; side < 2; ++side) {
                    const uint32_t c = n.children[size_t(side)];
                    if (c >= nodes.size() || parent[c] != i) continue;
                    const bool reaches = side == 0 ? tb.lo[n.axis] <= n.split + tol : tb.hi[n.axis] >= n.split - tol;
                    if (reaches) stack.push_back(c);
                }
                continue;
            }
            if (!triangle_overlaps_box(mesh.vertex(t, 0), mesh.vertex(t, 1), mesh.vertex(t, 2), padded(cell[i], tol)))
                continue;
            if (std::binary_search(sorted[i].begin(), sorted[i].end(), t)) continue;
            if (!problems.listing()) problems.count(i);
            else
                problems.add(i, "triangle " + std::to_string(t) + " overlaps leaf node " + std::to_string(i) +
                                    "'s cell " + box_words(cell[i]) +
                                    " (or touches it) but is not in its list: a ray could hit it there and miss it");
        }
    }
}

void check_grid(const StructureFile& f, const Mesh& mesh, Problems& problems) {
    const uint64_t n_tris = mesh.triangle_count();
    const float tol = containment_tolerance(mesh);
    if (!is_box(f.bounds)) {
        problems.add(std::nullopt, "\"bounds\" " + box_words(f.bounds) + " is not a box (lo <= hi, finite)");
        return;
    }
    const auto [nx, ny, nz] = f.resolution;
    const auto axis_ok = [](uint32_t n) { return n >= 1 && n <= kMaxGridCellsPerAxis; };
    if (!axis_ok(nx) || !axis_ok(ny) || !axis_ok(nz) || uint64_t(nx) * ny * nz > kMaxGridCells) {  // < 2^48: no wrap
        problems.add(std::nullopt, "\"resolution\" " + std::to_string(nx) + " x " + std::to_string(ny) + " x " +
                                       std::to_string(nz) + ": each 1 to " + std::to_string(kMaxGridCellsPerAxis) +
                                       ", and at most " + std::to_string(kMaxGridCells) + " cells in all");
        return;
    }
    const Overhang scene = overhang(mesh.bounds(), f.bounds);
    if (scene.amount > tol)
        problems.add(std::nullopt, "the mesh sticks out of \"bounds\" by " + number(scene.amount) + " on " + scene.face);
    std::vector<int32_t> entry_of(uint64_t(nx) * ny * nz, -1);
    if (f.cells.size() > size_t(INT32_MAX)) {
        problems.add(std::nullopt, "more cell entries than a grid has cells");
        return;
    }
    std::vector<std::vector<uint32_t>> sorted(f.cells.size());
    for (size_t e = 0; e < f.cells.size(); ++e) {
        const auto [i, j, k] = f.cells[e].cell;
        if (i >= nx || j >= ny || k >= nz) {
            problems.add(e, "cell entry " + std::to_string(e) + " is cell (" + std::to_string(i) + ", " +
                                std::to_string(j) + ", " + std::to_string(k) + "), outside the grid");
            continue;
        }
        const uint64_t id = i + uint64_t(nx) * (j + uint64_t(ny) * k);
        if (entry_of[id] >= 0) {
            problems.add(e, "cell entry " + std::to_string(e) + " repeats cell (" + std::to_string(i) + ", " +
                                std::to_string(j) + ", " + std::to_string(k) + ") of entry " +
                                std::to_string(entry_of[id]));
            continue;
        }
        entry_of[id] = int32_t(e);
        sorted[e] = f.cells[e].triangles;
        std::sort(sorted[e].begin(), sorted[e].end());
        if (!sorted[e].empty() && sorted[e].back() >= n_tris)
            problems.add(e, "cell entry " + std::to_string(e) + " lists " + std::to_string(sorted[e].back()) +
                                ", not a triangle: the mesh has " + std::to_string(n_tris));
    }
    uint64_t references = 0;
    for (const FileGridCell& c : f.cells) references += c.triangles.size();
    if (references >= uint64_t(UINT32_MAX)) {
        problems.add(std::nullopt, "the cells list " + std::to_string(references) + " triangles in all: at most 2^32 - 1");
        return;
    }
    // The planes as the grid walk places them.
    std::array<std::vector<float>, 3> planes;
    for (int a = 0; a < 3; ++a) planes[size_t(a)] = grid_axis_planes(f.bounds.lo[a], f.bounds.hi[a], int(f.resolution[size_t(a)]));
    auto cell_range = [&](int a, float lo, float hi) {
        const auto& p = planes[size_t(a)];
        const auto first = std::upper_bound(p.begin(), p.end(), lo) - p.begin() - 1;
        const auto last = std::lower_bound(p.begin(), p.end(), hi) - p.begin() - 1;
        const long n = long(p.size()) - 2;
        return std::pair<long, long>{std::clamp<long>(first, 0, n), std::clamp<long>(last, 0, n)};
    };
    for (uint32_t t = 0; t < n_tris; ++t) {
        const Aabb tb = padded(mesh.triangle_bounds(t), tol);
        const auto [i0, i1] = cell_range(0, tb.lo.x, tb.hi.x);
        const auto [j0, j1] = cell_range(1, tb.lo.y, tb.hi.y);
        const auto [k0, k1] = cell_range(2, tb.lo.z, tb.hi.z);
        for (long k = k0; k <= k1; ++k)
            for (long j = j0; j <= j1; ++j)
                for (long i = i0; i <= i1; ++i) {
                    const Aabb c{{planes[0][size_t(i)], planes[1][size_t(j)], planes[2][size_t(k)]},
                                 {planes[0][size_t(i) + 1], planes[1][size_t(j) + 1], planes[2][size_t(k) + 1]}};
                    if (!triangle_overlaps_box(mesh.vertex(t, 0), mesh.vertex(t, 1), mesh.vertex(t, 2),
                                               padded(c, tol)))
                        continue;
                    const int64_t e = entry_of[uint64_t(i) + uint64_t(nx) * (uint64_t(j) + uint64_t(ny) * uint64_t(k))];
                    if (e >= 0 && std::binary_search(sorted[size_t(e)].begin(), sorted[size_t(e)].end(), t)) continue;
                    const std::optional<uint64_t> entry = e < 0 ? std::nullopt : std::optional<uint64_t>(uint64_t(e));
                    if (!problems.listing()) problems.count(entry);
                    else
                        problems.add(entry,
                                     "triangle " + std::to_string(t) + " overlaps cell (" + std::to_string(i) + ", " +
                                         std::to_string(j) + ", " + std::to_string(k) +
                                         ") (or touches it) but is not listed there: a ray could hit it there and miss it");
                }
    }
}

}  // namespace

StructureCheck check_structure(const StructureFile& file, const Mesh& mesh, std::optional<uint32_t> mesh_crc,
                               size_t max_listed) {
    StructureCheck out;
    Problems problems(out, max_listed);
    check_mesh(file, mesh, mesh_crc, problems);
    if (file.mesh.triangles == mesh.triangle_count()) {
        if (file.type == AccelType::Bvh) check_bvh(file, mesh, problems);
        else if (file.type == AccelType::Kd) check_kd(file, mesh, problems);
        else check_grid(file, mesh, problems);
    }
    problems.finish();
    return out;
}

std::vector<Aabb> file_kd_cells(const StructureFile& f) {
    const size_t count = f.kd_nodes.size();
    std::vector<Aabb> cell(count, f.bounds);
    if (count == 0) return cell;
    std::vector<uint8_t> reached(count, 0);
    reached[0] = 1;
    std::vector<uint32_t> queue = {0};  // breadth first: a parent's cell before its children's
    for (size_t q = 0; q < queue.size(); ++q) {
        const FileKdNode& n = f.kd_nodes[queue[q]];
        if (n.is_leaf()) continue;
        for (int side = 0; side < 2; ++side) {
            const uint32_t c = n.children[size_t(side)];
            if (c >= count || reached[c]) continue;
            reached[c] = 1;
            cell[c] = cell[queue[q]];
            if (side == 0) cell[c].hi[n.axis] = std::min(cell[c].hi[n.axis], n.split);
            else cell[c].lo[n.axis] = std::max(cell[c].lo[n.axis], n.split);
            queue.push_back(c);
        }
    }
    return cell;
}

// [SECTION] Our traversal over a file's structure

namespace {

Bvh binary_bvh_of(const StructureFile& f, const Mesh& mesh) {
    Bvh bvh;
    if (f.bvh_nodes.empty()) return bvh;
    // Our layout: the root alone, then each node's two children side by side.
    std::vector<std::pair<uint32_t, uint32_t>> queue = {{0u, 0u}};  // (file node, our node)
    bvh.nodes.resize(1);
    for (size_t q = 0; q < queue.size(); ++q) {
        const auto [from, to] = queue[q];
        const FileBvhNode& n = f.bvh_nodes[from];
        BvhNode& out = bvh.nodes[to];
        out.bounds = n.box;
        if (n.interior) {
            const auto first = uint32_t(bvh.nodes.size());
            bvh.nodes[to].first = first;
            bvh.nodes[to].count = 0;
            bvh.nodes.resize(bvh.nodes.size() + 2);
            queue.push_back({n.children[0], first});
            queue.push_back({n.children[1], first + 1});
        } else {
            out.first = uint32_t(bvh.prim_ids.size());
            out.count = uint32_t(n.count);
            bvh.prim_ids.insert(bvh.prim_ids.end(), f.order.begin() + long(n.first),
                                f.order.begin() + long(n.first + n.count));
        }
    }
    for (uint32_t id : bvh.prim_ids) bvh.triangles.push_back(mesh.triangle(id));
    return bvh;
}

template <int W>
WideBvh<W> wide_bvh_of(const StructureFile& f, const Mesh& mesh) {
    WideBvh<W> wide;
    const auto& nodes = f.bvh_nodes;
    if (nodes.empty()) return wide;
    auto append_leaf = [&](const FileBvhNode& n) {
        const auto first = uint32_t(wide.prim_ids.size());
        wide.prim_ids.insert(wide.prim_ids.end(), f.order.begin() + long(n.first), f.order.begin() + long(n.first + n.count));
        return first;
    };
    wide.root_bounds = nodes[0].box;
    if (!nodes[0].interior) {
        wide.root_first = append_leaf(nodes[0]);
        wide.root_count = uint32_t(nodes[0].count);
    } else {
        std::vector<uint32_t> queue = {0u};  // file nodes, wide node k = queue[k]
        for (size_t q = 0; q < queue.size(); ++q) {
            const FileBvhNode& n = nodes[queue[q]];
            typename WideBvh<W>::Node node{};
            node.child_count = uint8_t(n.children.size());
            for (int i = 0; i < W; ++i) {
                node.first[i] = 0;
                node.count[i] = 0;
                if (i >= int(n.children.size())) {
                    node.boxes.set(i, Aabb{});
                    continue;
                }
                const FileBvhNode& c = nodes[n.children[size_t(i)]];
                node.boxes.set(i, c.box);
                if (c.interior) {
                    node.first[i] = uint32_t(queue.size());
                    queue.push_back(n.children[size_t(i)]);
                } else {
                    node.first[i] = append_leaf(c);
                    node.count[i] = uint16_t(c.count);
                }
            }
            wide.nodes.push_back(node);
        }
    }
    TriangleArray triangles;
    for (uint32_t id : wide.prim_ids) triangles.push_back(mesh.triangle(id));
    wide.make_leaf_lanes(triangles);
    wide.build_stats.width = W;
    return wide;
}

KdTree kd_tree_of(const StructureFile& f, const Mesh& mesh) {
    KdTree kd;
    kd.bounds = f.bounds;
    kd.build_stats.triangles = uint32_t(mesh.triangle_count());
    if (f.kd_nodes.empty()) return kd;
    // Our layout: each node's two children side by side, the lower first.
    std::vector<std::pair<uint32_t, uint32_t>> queue = {{0u, 0u}};
    kd.nodes.resize(1);
    for (size_t q = 0; q < queue.size(); ++q) {
        const auto [from, to] = queue[q];
        const FileKdNode& n = f.kd_nodes[from];
        if (n.is_leaf()) {
            kd.nodes[to] = KdNode::leaf(uint32_t(kd.prim_ids.size()), uint32_t(n.triangles.size()));
            kd.prim_ids.insert(kd.prim_ids.end(), n.triangles.begin(), n.triangles.end());
            continue;
        }
        const auto first = uint32_t(kd.nodes.size());
        kd.nodes[to] = KdNode::interior(n.axis, n.split, first);
        kd.nodes.resize(kd.nodes.size() + 2);
        queue.push_back({n.children[0], first});
        queue.push_back({n.children[1], first + 1});
    }
    kd.triangles = make_triangles(mesh, kd.prim_ids);
    kd.make_leaf_lanes();
    kd.build_stats.nodes = uint32_t(kd.nodes.size());
    kd.build_stats.references = kd.prim_ids.size();
    return kd;
}

UniformGrid grid_of(const StructureFile& f, const Mesh& mesh) {
    UniformGrid g;
    g.bounds = f.bounds;
    for (int a = 0; a < 3; ++a) {
        g.res[size_t(a)] = int(f.resolution[size_t(a)]);
        g.planes[size_t(a)] = grid_axis_planes(f.bounds.lo[a], f.bounds.hi[a], g.res[size_t(a)]);
    }
    const uint64_t cells = uint64_t(g.res[0]) * uint64_t(g.res[1]) * uint64_t(g.res[2]);
    std::vector<const FileGridCell*> entry(cells, nullptr);
    for (const FileGridCell& c : f.cells) entry[g.cell_id(int(c.cell[0]), int(c.cell[1]), int(c.cell[2]))] = &c;
    g.cell_start.assign(cells + 1, 0);
    for (uint64_t c = 0; c < cells; ++c) {
        g.cell_start[c + 1] = g.cell_start[c];
        if (!entry[c]) continue;
        std::vector<uint32_t> ids = entry[c]->triangles;
        std::sort(ids.begin(), ids.end());  // the walk's order: increasing id
        g.tri_ids.insert(g.tri_ids.end(), ids.begin(), ids.end());
        g.cell_start[c + 1] += uint32_t(ids.size());
    }
    g.triangles = make_triangles(mesh);
    g.build_stats.triangles = uint32_t(mesh.triangle_count());
    return g;
}

template <class S>
std::shared_ptr<const Accelerator> adapt(S&& s) {
    return std::make_shared<AcceleratorFor<std::decay_t<S>>>(std::forward<S>(s));
}

double area_ratio(const Aabb& box, double root_area) {
    return root_area > 0 ? double(box.area()) / root_area : 0.0;
}

void add_leaf_size(StructureFigures& fig, uint64_t size) {
    if (fig.leaf_sizes.size() <= size) fig.leaf_sizes.resize(size + 1, 0);
    ++fig.leaf_sizes[size];
}

}  // namespace

namespace {

/// structure_accelerator for a file check_structure has passed.
std::shared_ptr<const Accelerator> lay_out(const StructureFile& file, const Mesh& mesh) {
    switch (file.type) {
        case AccelType::Kd: return adapt(kd_tree_of(file, mesh));
        case AccelType::Grid: return adapt(grid_of(file, mesh));
        default: break;
    }
    const int arity = file.max_arity();
    if (arity <= 2) return adapt(binary_bvh_of(file, mesh));
    if (arity <= 4) return adapt(wide_bvh_of<4>(file, mesh));
    return adapt(wide_bvh_of<8>(file, mesh));
}

}  // namespace

Expected<std::shared_ptr<const Accelerator>> structure_accelerator(const StructureFile& file, const Mesh& mesh) {
    if (!check_structure(file, mesh, std::nullopt, 0).valid())
        return Error{"the structure is not valid: accelviz check says why"};
    return lay_out(file, mesh);
}

StructureFigures measure_structure(const StructureFile& f, const Mesh& mesh, const Accelerator& accel,
                                   std::span<const Ray> rays, const Accelerator& reference, SahCosts costs) {
    StructureFigures fig;
    const double triangles = double(std::max<size_t>(mesh.triangle_count(), 1));
    uint64_t references = 0, children = 0;
    if (f.type == AccelType::Bvh && !f.bvh_nodes.empty()) {
        const double root_area = f.bvh_nodes[0].box.area();
        std::vector<std::pair<uint32_t, uint32_t>> stack = {{0u, 0u}};
        while (!stack.empty()) {
            const auto [i, depth] = stack.back();
            stack.pop_back();
            const FileBvhNode& n = f.bvh_nodes[i];
            ++fig.nodes;
            const double p = area_ratio(n.box, root_area);
            if (n.interior) {
                ++fig.interior;
                children += n.children.size();
                fig.sah_cost += p * costs.trav;
                for (uint32_t c : n.children) stack.push_back({c, depth + 1});
                continue;
            }
            ++fig.leaves;
            fig.depth = std::max(fig.depth, depth);
            references += n.count;
            fig.sah_cost += p * double(n.count) * costs.isect;
            add_leaf_size(fig, n.count);
        }
    } else if (f.type == AccelType::Kd && !f.kd_nodes.empty()) {
        const double root_area = f.bounds.area();
        struct Item {
            uint32_t node, depth;
            Aabb cell;
        };
        std::vector<Item> stack = {{0u, 0u, f.bounds}};
        while (!stack.empty()) {
            const Item it = stack.back();
            stack.pop_back();
            const FileKdNode& n = f.kd_nodes[it.node];
            ++fig.nodes;
            const double p = area_ratio(it.cell, root_area);
            if (!n.is_leaf()) {
                ++fig.interior;
                children += 2;
                fig.sah_cost += p * costs.trav;
                Aabb lower = it.cell, upper = it.cell;
                lower.hi[n.axis] = n.split;
                upper.lo[n.axis] = n.split;
                stack.push_back({n.children[1], it.depth + 1, upper});
                stack.push_back({n.children[0], it.depth + 1, lower});
                continue;
            }
            ++fig.leaves;
            if (n.triangles.empty()) ++fig.empty_leaves;
            fig.depth = std::max(fig.depth, it.depth);
            references += n.triangles.size();
            fig.sah_cost += p * double(n.triangles.size()) * costs.isect;
            add_leaf_size(fig, n.triangles.size());
        }
    } else if (f.type == AccelType::Grid) {
        // A grid's cost in the same terms: a ray that enters a cell steps once (C_trav) and
        // tests its triangles; the chance to enter a cell is its area over the grid's.
        const double root_area = f.bounds.area();
        const Vec3 e = f.bounds.extent();
        const Aabb one_cell{{0, 0, 0},
                            {e.x / float(f.resolution[0]), e.y / float(f.resolution[1]), e.z / float(f.resolution[2])}};
        const double p = area_ratio(one_cell, root_area);
        const uint64_t cells = uint64_t(f.resolution[0]) * f.resolution[1] * f.resolution[2];
        fig.nodes = fig.leaves = cells;
        fig.empty_leaves = cells - f.cells.size();
        for (const FileGridCell& c : f.cells) {
            references += c.triangles.size();
            add_leaf_size(fig, c.triangles.size());
            if (c.triangles.empty()) ++fig.empty_leaves;
        }
        fig.sah_cost = double(cells) * p * costs.trav + p * double(references) * costs.isect;
    }
    fig.avg_children = fig.interior ? double(children) / double(fig.interior) : 0.0;
    fig.references = double(references) / triangles;
    Counters counters;
    for (const Ray& ray : rays) {
        CountingObserver counter;
        const Hit hit = accel.intersect_closest(ray, counter);
        counters += counter.counters;
        const Hit want = reference.intersect_closest(ray);
        if (hit.found() != want.found() || (want.found() && (hit.tri != want.tri || hit.t != want.t)))
            ++fig.mismatches;
    }
    fig.rays = rays.size();
    const double n = double(std::max<size_t>(rays.size(), 1));
    fig.nodes_per_ray = double(counters.nodes_visited) / n;
    fig.box_tests_per_ray = double(counters.box_tests) / n;
    fig.triangle_tests_per_ray = double(counters.triangle_tests) / n;
    return fig;
}

}  // namespace accelviz

namespace accelviz {

Expected<CheckedStructureFile> read_and_check_structure(const std::string& path, const Mesh& mesh,
                                                        std::optional<uint32_t> mesh_crc, size_t max_listed) {
    auto file = read_structure_file(path);
    if (!file) return Error{file.error()};
    CheckedStructureFile out;
    out.check = check_structure(*file, mesh, mesh_crc, max_listed);
    out.file = std::make_shared<const StructureFile>(std::move(*file));
    if (out.check.valid()) out.accel = lay_out(*out.file, mesh);
    return out;
}

Expected<std::shared_ptr<const Accelerator>> load_structure_file(const std::string& path, const Mesh& mesh,
                                                                 const std::string& source) {
    std::optional<uint32_t> crc;
    if (!source.empty()) {
        auto c = mesh_crc32(source, mesh);
        if (!c) return Error{c.error()};
        crc = *c;
    }
    auto checked = read_and_check_structure(path, mesh, crc, 1);
    if (!checked) return Error{checked.error()};
    const StructureCheck& check = checked->check;
    if (!check.valid())
        return Error{path + " is not a valid structure over this mesh (" + std::to_string(check.problem_count) +
                     " problem" + (check.problem_count == 1 ? "" : "s") + "; the first: " +
                     check.problems.front().message + "): accelviz check lists them"};
    return checked->accel;
}

}  // namespace accelviz
