#include "core/accel/bsp_tree.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "core/util/large_array.h"

namespace accelviz {

std::optional<Error> validate(const BspConfig& c) {
    if (c.max_depth < 1 || c.max_depth > kBspMaxDepth)
        return Error{"--bsp-max-depth must be in 1.." + std::to_string(kBspMaxDepth)};
    if (c.leaf_size < 1) return Error{"--leaf-size must be at least 1"};
    if (c.candidates < 1 || c.candidates > kBspMaxCandidates)
        return Error{"--bsp-candidates must be in 1.." + std::to_string(kBspMaxCandidates)};
    if (!(c.cost_trav >= 0) || !std::isfinite(c.cost_trav)) return Error{"--cost-trav must be finite and >= 0"};
    if (!(c.cost_isect > 0) || !std::isfinite(c.cost_isect)) return Error{"--cost-isect must be finite and > 0"};
    if (!(c.empty_bonus >= 0 && c.empty_bonus < 1)) return Error{"bsp empty_bonus must be in [0, 1)"};
    if (!(c.max_duplication >= 1.0)) return Error{"bsp max_duplication must be >= 1"};
    return std::nullopt;
}

namespace {

/// Signed distance in double: the sign decides a side, near the plane too.
double distance(const Plane& p, Vec3 v) {
    return double(p.normal.x) * v.x + double(p.normal.y) * v.y + double(p.normal.z) * v.z - double(p.offset);
}

/// Sutherland–Hodgman against one half-space, into `out` (which it returns the
/// size of); `inside(v)` >= 0 for the kept side.
template <class Inside, class Out>
void clip_into(const Vec3* in, int n, Inside inside, Out&& push) {
    for (int i = 0; i < n; ++i) {
        const Vec3 a = in[i], b = in[(i + 1) % n];
        const double da = inside(a), db = inside(b);
        if (da >= 0) push(a);
        if ((da >= 0) != (db >= 0)) {
            const double s = da / (da - db);
            push(Vec3{float(a.x + s * (b.x - a.x)), float(a.y + s * (b.y - a.y)), float(a.z + s * (b.z - a.z))});
        }
    }
}

/// The part of a triangle inside its node's cell grown by the padding: a convex
/// polygon of up to kMaxVertices corners (a triangle cut by k planes has at most
/// 3 + k). When a cut would need more, the piece keeps its larger uncut polygon:
/// a superset, so still safe, only less tight.
struct Piece {
    static constexpr int kMaxVertices = 9;
    uint32_t tri = 0;
    uint8_t count = 0;
    std::array<Vec3, kMaxVertices> v;

    /// This piece on one side of `plane` grown by `pad` (nothing if none of it is).
    std::optional<Piece> side(const Plane& plane, bool back, float pad) const {
        Piece out;
        out.tri = tri;
        bool overflow = false;
        clip_into(v.data(), count,
                  [&](Vec3 p) { return back ? double(pad) - distance(plane, p) : distance(plane, p) + double(pad); },
                  [&](Vec3 p) {
                      if (out.count < kMaxVertices) out.v[out.count++] = p;
                      else overflow = true;
                  });
        if (out.count == 0) return std::nullopt;
        return overflow ? *this : out;
    }
};

/// Which sides of `plane` a piece comes within `pad` of.
struct Sides {
    bool back = false, front = false;
};
Sides sides_of(const Piece& piece, const Plane& plane, float pad) {
    double lo = kInfinity, hi = -kInfinity;
    for (int i = 0; i < piece.count; ++i) {
        const double d = distance(plane, piece.v[size_t(i)]);
        lo = std::min(lo, d);
        hi = std::max(hi, d);
    }
    return {lo < pad, hi > -pad};
}

Aabb bounds_of(const Piece& piece) {
    Aabb b;
    for (int i = 0; i < piece.count; ++i) b.grow(piece.v[size_t(i)]);
    return b;
}

/// The plane of triangle `tri`, if it has one (not degenerate).
std::optional<Plane> triangle_plane(const Mesh& mesh, uint32_t tri) {
    const Vec3d p0 = to_double(mesh.vertex(tri, 0));
    const Vec3d n = cross(to_double(mesh.vertex(tri, 1)) - p0, to_double(mesh.vertex(tri, 2)) - p0);
    const double len = std::sqrt(dot(n, n));
    if (!(len > 0) || !std::isfinite(len)) return std::nullopt;
    const Vec3d u = n * (1.0 / len);
    return Plane{to_float(u), float(dot(u, p0))};
}

/// The six faces of a box, as polygons.
std::vector<Polygon> box_faces(const Aabb& b) {
    auto corner = [&](int i) { return Vec3{i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z}; };
    const int faces[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
    std::vector<Polygon> out;
    for (const auto& f : faces) out.push_back({corner(f[0]), corner(f[1]), corner(f[2]), corner(f[3])});
    return out;
}

/// A polygon's plane by Newell's method (robust when corners nearly repeat).
std::optional<Plane> polygon_plane(const Polygon& poly) {
    Vec3d n{0, 0, 0}, centre{0, 0, 0};
    for (size_t i = 0; i < poly.size(); ++i) {
        const Vec3d a = to_double(poly[i]), b = to_double(poly[(i + 1) % poly.size()]);
        n = n + Vec3d{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
        centre = centre + a;
    }
    const double len = std::sqrt(dot(n, n));
    if (!(len > 0)) return std::nullopt;
    const Vec3d u = n * (1.0 / len);
    return Plane{to_float(u), float(dot(u, centre * (1.0 / double(poly.size()))))};
}

/// `plane` inside the convex cell with these faces: a square on the plane larger
/// than the cell, cut by the plane of every face, keeping the side of the cell's
/// centroid (the mean of its corners: inside, as the cell is convex; the centre
/// of its bounds need not be).
Polygon plane_in_cell(const Plane& plane, const std::vector<Polygon>& faces, const Aabb& cell_bounds) {
    Vec3d mean{0, 0, 0};
    size_t corners = 0;
    for (const Polygon& f : faces)
        for (const Vec3& p : f) {
            mean = mean + to_double(p);
            ++corners;
        }
    if (corners == 0) return {};
    const Vec3 c = to_float(mean * (1.0 / double(corners)));
    // Larger than the cell whatever its units (an absolute margin would swamp a
    // small scene's cells with the square's rounding).
    const float r = 1.01f * length(cell_bounds.extent());
    const Vec3 n = plane.normal;
    const Vec3 q = c - n * plane.distance(c);
    const Vec3 helper = std::abs(n.x) < 0.9f ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    const Vec3 u = normalize(cross(n, helper)), v = cross(n, u);
    Polygon poly = {q + (u + v) * r, q + (v - u) * r, q - (u + v) * r, q + (u - v) * r};
    for (const Polygon& face : faces) {
        if (face.size() < 3 || poly.empty()) continue;
        // The face's plane, oriented so that the cell's centroid is on its back.
        std::optional<Plane> fp = polygon_plane(face);
        if (!fp) continue;
        if (fp->distance(c) > 0) fp = Plane{fp->normal * -1.0f, -fp->offset};
        Polygon out;
        clip_into(poly.data(), int(poly.size()), [&](Vec3 p) { return -distance(*fp, p); },
                  [&](Vec3 p) { out.push_back(p); });
        poly = std::move(out);
    }
    return poly;
}

/// The part of the convex cell with these faces on one side of `plane`: each face
/// cut, and `cap` (the plane's own polygon in the cell, plane_in_cell) as the new face.
std::vector<Polygon> split_cell(const std::vector<Polygon>& faces, const Plane& plane, bool back, const Polygon& cap) {
    std::vector<Polygon> out;
    for (const Polygon& f : faces) {
        Polygon cut = clip_polygon(f, plane, back);
        if (cut.size() >= 3) out.push_back(std::move(cut));
    }
    if (cap.size() >= 3) out.push_back(cap);
    return out;
}

double polygon_area(const Polygon& poly) {
    Vec3d n{0, 0, 0};
    for (size_t i = 0; i < poly.size(); ++i) {
        const Vec3d a = to_double(poly[i]), b = to_double(poly[(i + 1) % poly.size()]);
        n = n + cross(a, b);
    }
    return 0.5 * std::sqrt(dot(n, n));
}

/// A cell: its faces, their bounds and its surface area (the SAH's A).
struct Cell {
    std::vector<Polygon> faces;
    Aabb bounds;
    double area = 0;

    explicit Cell(std::vector<Polygon> f) : faces(std::move(f)) {
        for (const Polygon& p : faces) {
            area += polygon_area(p);
            for (const Vec3& v : p) bounds.grow(v);
        }
    }
    /// The plane's polygon inside the cell: the face both parts get.
    Polygon cap(const Plane& plane) const { return plane_in_cell(plane, faces, bounds); }
    /// The part on one side of `plane`, whose polygon in the cell is `cap` (its bounds
    /// kept inside this cell's: the cut's corners are rounded to float).
    Cell side(const Plane& plane, bool back, const Polygon& cap) const {
        Cell part(split_cell(faces, plane, back, cap));
        if (!part.bounds.empty()) part.bounds = {max(part.bounds.lo, bounds.lo), min(part.bounds.hi, bounds.hi)};
        return part;
    }

    /// True if `plane` cuts the cell: some corner lies beyond `pad` on either side.
    bool cut_by(const Plane& plane, float pad) const {
        double lo = kInfinity, hi = -kInfinity;
        for (const Polygon& f : faces)
            for (const Vec3& v : f) {
                const double d = distance(plane, v);
                lo = std::min(lo, d);
                hi = std::max(hi, d);
            }
        return lo < -double(pad) && hi > double(pad);
    }

    /// The surface areas of the two parts `plane` cuts the cell into, without
    /// making them: each face's part on either side, and the cut itself, a convex
    /// polygon through the points where the faces' edges cross the plane (ordered
    /// by angle around their mean).
    std::pair<double, double> side_areas(const Plane& plane) const {
        double back = 0, front = 0;
        std::vector<Vec3> crossings;
        Polygon b, f;
        for (const Polygon& face : faces) {
            b.clear();
            f.clear();
            for (size_t i = 0; i < face.size(); ++i) {
                const Vec3 p = face[i], q = face[(i + 1) % face.size()];
                const double dp = distance(plane, p), dq = distance(plane, q);
                if (dp <= 0) b.push_back(p);
                if (dp >= 0) f.push_back(p);
                if (dp == 0) crossings.push_back(p);  // a corner on the plane is a corner of the cut
                if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) {
                    const double s = dp / (dp - dq);
                    const Vec3 x{float(p.x + s * (q.x - p.x)), float(p.y + s * (q.y - p.y)), float(p.z + s * (q.z - p.z))};
                    b.push_back(x);
                    f.push_back(x);
                    crossings.push_back(x);
                }
            }
            if (b.size() >= 3) back += polygon_area(b);
            if (f.size() >= 3) front += polygon_area(f);
        }
        if (crossings.size() >= 3) {
            Vec3d mean{0, 0, 0};
            for (const Vec3& x : crossings) mean = mean + to_double(x);
            const Vec3 c = to_float(mean * (1.0 / double(crossings.size())));
            const Vec3 n = plane.normal;
            const Vec3 u = normalize(cross(n, std::abs(n.x) < 0.9f ? Vec3{1, 0, 0} : Vec3{0, 1, 0})), v = cross(n, u);
            std::sort(crossings.begin(), crossings.end(), [&](const Vec3& x, const Vec3& y) {
                return std::atan2(dot(x - c, v), dot(x - c, u)) < std::atan2(dot(y - c, v), dot(y - c, u));
            });
            const double cap = polygon_area(crossings);
            back += cap;
            front += cap;
        }
        return {back, front};
    }
};

/// A candidate plane weighed by the surface area heuristic (the lecture's SAH, as
/// the KD tree's): C_trav + C_isect · (A_back · N_back + A_front · N_front) / A,
/// with A the cells' surface areas (of their polyhedra), discounted by the empty-space bonus when
/// a side is empty. A triangle cut by the plane counts on both sides.
struct Score {
    double cost = kInfinity;
    bool progress = false;  ///< a side holds fewer pieces than the node
};
Score score(const std::vector<Piece>& pieces, const std::vector<Aabb>& piece_bounds, const Plane& plane, float pad,
            const Cell& cell, const BspConfig& config) {
    // A big node is weighed on an even sample: the counts are scaled back to n.
    const size_t n = pieces.size(), stride = std::max<size_t>(1, n / 4096);
    size_t back = 0, front = 0, sampled = 0;
    for (size_t i = 0; i < n; i += stride, ++sampled) {
        // The piece's box settles most pieces without their corners.
        const Aabb& b = piece_bounds[i];
        const Vec3 centre = b.center(), half = b.extent() * 0.5f;
        const double reach = std::abs(plane.normal.x) * half.x + std::abs(plane.normal.y) * half.y +
                             std::abs(plane.normal.z) * half.z;
        const double d = distance(plane, centre);
        Sides sd;
        if (d - reach >= pad) sd.front = true;
        else if (d + reach <= -pad) sd.back = true;
        else sd = sides_of(pieces[i], plane, pad);
        back += sd.back;
        front += sd.front;
    }
    Score s;
    s.progress = back < sampled || front < sampled;
    if (!s.progress) return s;
    if (!(cell.area > 0)) return s;
    const double scale = double(n) / double(sampled);
    const auto [a_back, a_front] = cell.side_areas(plane);
    s.cost = config.cost_trav +
             config.cost_isect * scale * (a_back * double(back) + a_front * double(front)) / cell.area;
    if (back == 0 || front == 0) s.cost *= 1.0 - config.empty_bonus;
    return s;
}

/// A split counts this part of its node's progress units at once (count_part): a
/// tree some dozens of levels deep does about that share of its work per level.
constexpr uint64_t kSplitParts = 16;
/// A node of millions of pieces takes seconds: its loops ask for a cancel this often.
constexpr size_t kPiecesPerCancelCheck = 16384;

struct WorkItem {
    uint32_t node;
    uint32_t depth;
    Cell cell;
    std::vector<Piece> pieces;
    uint64_t progress_units;
};

}  // namespace

Polygon clip_polygon(const Polygon& polygon, const Plane& plane, bool back, float pad) {
    Polygon out;
    clip_into(polygon.data(), int(polygon.size()),
              [&](Vec3 p) { return back ? double(pad) - distance(plane, p) : distance(plane, p) + double(pad); },
              [&](Vec3 p) { out.push_back(p); });
    return out;
}

Expected<BspTree> build_bsp_tree(const Mesh& mesh, const BspConfig& config, WorkProgress* shared_progress) {
    const auto start = std::chrono::steady_clock::now();
    if (auto err = validate(config)) return *err;
    BspTree tree;
    BspBuildStats& st = tree.build_stats;
    const float pad = tree.begin_build(mesh, config, start);
    if (st.triangles == 0) return tree;
    const double budget = config.max_duplication * st.triangles;
    start_stage(shared_progress, PartitionProgress::kTotal);
    PartitionProgress progress(shared_progress);

    std::vector<Piece> root = make_prefaulted<std::vector<Piece>>(st.triangles);
    for (uint32_t t = 0; t < st.triangles; ++t) {
        if (t % kPiecesPerCancelCheck == 0 && progress.cancelled()) return WorkProgress::cancelled_error();
        root[t].tri = t;
        root[t].count = 3;
        for (int k = 0; k < 3; ++k) root[t].v[size_t(k)] = mesh.vertex(t, k);
    }
    SubtreeCounts counts;
    uint64_t live = st.triangles;  // references in leaves and in work not done yet
    tree.nodes.emplace_back();
    tree.shapes.cell_bounds.resize(1);
    tree.shapes.split_polygons.resize(1);
    std::vector<WorkItem> work;
    work.push_back({0, 0, Cell(box_faces(tree.bounds)), std::move(root), PartitionProgress::kTotal});
    while (!work.empty()) {
        if (progress.cancelled()) return WorkProgress::cancelled_error();
        WorkItem item = std::move(work.back());
        work.pop_back();
        const size_t n = item.pieces.size();
        std::optional<Plane> best;
        bool from_triangle = false;
        if (n > size_t(config.leaf_size) && int(item.depth) < config.max_depth) {
            std::vector<Aabb> piece_bounds = make_prefaulted<std::vector<Aabb>>(n);
            Aabb content;
            for (size_t i = 0; i < n; ++i) {
                if (i % kPiecesPerCancelCheck == 0 && progress.cancelled()) return WorkProgress::cancelled_error();
                piece_bounds[i] = bounds_of(item.pieces[i]);
                content.grow(piece_bounds[i]);
            }
            // A leaf costs n tests; a split must promise less.
            Score best_score;
            best_score.cost = double(n) * config.cost_isect;
            auto consider = [&](const Plane& plane, bool triangle) {
                // Only a plane that cuts the cell (corners beyond the padding on both
                // sides): one along a face, or an ancestor's again, would make a cell
                // of no volume, which rounding can make look like progress.
                if (!item.cell.cut_by(plane, pad)) return;
                const Score s = score(item.pieces, piece_bounds, plane, pad, item.cell, config);
                if (s.progress && s.cost < best_score.cost) {
                    best_score = s;
                    best = plane;
                    from_triangle = triangle;
                }
            };
            // Triangle planes, from an even sample of the node's triangles.
            const size_t tries = std::min(n, size_t(config.candidates));
            for (size_t k = 0; k < tries; ++k)
                if (const auto plane = triangle_plane(mesh, item.pieces[k * n / tries].tri)) consider(*plane, true);
            // And on each axis: the middle of the contents, and their two ends (a cut
            // there leaves empty space on one side, which a ray then skips).
            // (Twice the padding beyond the contents: within it they would count on both sides.)
            for (int a = 0; a < 3; ++a)
                for (const float at : {content.center()[a], content.lo[a] - 2 * pad, content.hi[a] + 2 * pad}) {
                    if (!(at > item.cell.bounds.lo[a] + pad && at < item.cell.bounds.hi[a] - pad)) continue;
                    Plane axis_plane{{0, 0, 0}, at};
                    axis_plane.normal[a] = 1.0f;
                    consider(axis_plane, false);
                }
        }
        std::vector<Piece> back, front;
        if (best) {
            for (size_t i = 0; i < n; ++i) {
                if (i % kPiecesPerCancelCheck == 0 && progress.cancelled()) return WorkProgress::cancelled_error();
                const Piece& p = item.pieces[i];
                const Sides sd = sides_of(p, *best, pad);
                if (sd.back)
                    if (auto piece = p.side(*best, true, pad)) back.push_back(*piece);
                if (sd.front)
                    if (auto piece = p.side(*best, false, pad)) front.push_back(*piece);
            }
            // The sample promised progress; the whole node must show it too.
            if (back.size() >= n && front.size() >= n) {
                best.reset();
                ++counts.no_progress;
            } else if (double(live) + double(back.size() + front.size()) - double(n) > budget) {
                best.reset();
                counts.budget_hit = true;
            }
        }
        tree.shapes.cell_bounds[item.node] = item.cell.bounds;
        if (!best) {
            BspNode& leaf = tree.nodes[item.node];
            leaf = BspNode{{}, uint32_t(tree.prim_ids.size()), uint32_t(n), true, false};
            for (const Piece& p : item.pieces) tree.prim_ids.push_back(p.tri);
            counts.add_leaf(n, item.depth, config.max_depth, config.leaf_size);
            progress.leaf_done(item.progress_units);
            continue;
        }
        live = live + back.size() + front.size() - n;
        const uint32_t first = uint32_t(tree.nodes.size());
        tree.nodes[item.node] = BspNode{*best, first, 0, false, from_triangle};
        (from_triangle ? st.triangle_planes : st.axis_planes) += 1;
        tree.nodes.resize(tree.nodes.size() + 2);
        tree.shapes.cell_bounds.resize(tree.nodes.size());
        tree.shapes.split_polygons.resize(tree.nodes.size());
        Polygon& cap = tree.shapes.split_polygons[item.node];
        cap = item.cell.cap(*best);
        // This node's own work counts now (1/kSplitParts of its units): the tree is built
        // one node at a time, and the first leaf of a big scene comes seconds after the root.
        const uint64_t units = progress.count_part(item.progress_units, kSplitParts);
        const uint64_t back_units = PartitionProgress::share_of(units, back.size(), back.size() + front.size());
        // Front pushed first: the back child is built first (depth first, construction order).
        work.push_back({first + 1, item.depth + 1, item.cell.side(*best, false, cap), std::move(front),
                        units - back_units});
        work.push_back({first, item.depth + 1, item.cell.side(*best, true, cap), std::move(back), back_units});
    }
    progress.flush();  // the tree's stage ends here; the leaf-order copy is the next
    counts.write_to(st);
    tree.end_build(mesh,
                   {.parts = "nodes",
                    .leaves_at_depth_limit = st.leaves_at_depth_limit,
                    .depth_limit = config.max_depth,
                    .leaf_size = config.leaf_size,
                    .not_split = counts.no_progress,
                    .not_split_why = "the cheapest plane on a sample of their triangles separated none of them",
                    .budget_hit = counts.budget_hit,
                    .max_duplication = config.max_duplication},
                   start, shared_progress);
    return tree;
}

nlohmann::json BspTree::config() const {
    const BspConfig& c = build_config;
    return {{"max_depth", c.max_depth},
            {"leaf_size", c.leaf_size},
            {"candidates", c.candidates},
            {"cost_trav", c.cost_trav},
            {"cost_isect", c.cost_isect},
            {"empty_bonus", c.empty_bonus},
            {"mailbox", c.mailbox},
            {"triangle_test", std::string(to_string(triangle_test))}};
}

nlohmann::json BspTree::stats() const {
    nlohmann::json j = partition_stats_json(build_stats);
    j["triangle_planes"] = build_stats.triangle_planes;
    j["axis_planes"] = build_stats.axis_planes;
    // The cells' bounds and planes' polygons kept for drawing (not in memory_bytes,
    // which counts what tracing reads).
    uint64_t shape_bytes = shapes.cell_bounds.size() * sizeof(Aabb);
    for (const Polygon& p : shapes.split_polygons) shape_bytes += sizeof(Polygon) + p.size() * sizeof(Vec3);
    j["shape_bytes"] = shape_bytes;
    return j;
}

}  // namespace accelviz
