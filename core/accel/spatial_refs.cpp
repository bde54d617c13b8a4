#include "core/accel/spatial_refs.h"

#include <array>
#include <optional>
#include <sstream>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/geometry/triangle_box.h"

namespace accelviz {

PartRule part_rule(ClipMode mode) { return mode == ClipMode::Box ? PartRule::BoxOverlap : PartRule::Clipped; }

std::string_view to_string(ClipMode mode) { return mode == ClipMode::Box ? "box" : "exact"; }

std::optional<ClipMode> parse_clip_mode(std::string_view name) {
    if (name == "box") return ClipMode::Box;
    if (name == "exact") return ClipMode::Exact;
    return std::nullopt;
}

const std::vector<std::string>& clip_mode_names() {
    static const std::vector<std::string> names = {"box", "exact"};
    return names;
}

SpatialRefs root_references(const Mesh& mesh, float pad) {
    SpatialRefs refs = make_prefaulted<SpatialRefs>(mesh.triangle_count());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, refs.size(), kRefsToShareOut), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t t = r.begin(); t < r.end(); ++t) refs[t] = {uint32_t(t), padded(mesh.triangle_bounds(uint32_t(t)), pad)};
    });
    return refs;
}

CornerTriples corner_triples(const Mesh& mesh, std::span<const uint32_t> order) {
    CornerTriples triples = make_prefaulted<CornerTriples>(mesh.triangle_count());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, triples.size(), kRefsToShareOut),
                      [&](const tbb::blocked_range<size_t>& r) {
                          for (size_t k = r.begin(); k < r.end(); ++k) {
                              const size_t t = order.empty() ? k : order[k];
                              for (int c = 0; c < 3; ++c) triples[k][c] = mesh.vertex(t, c);
                          }
                      });
    return triples;
}

namespace {

/// The bounds of `in_cell` (a triangle clipped to its padded cell) within `clip_box`
/// (a child grown by pad, child `o`): the polygon cut at the planes of the axes in
/// `cuts`, the axes whose plane the reference's box straddles; the last cut only
/// bounds the part. (On an axis whose plane the box lies on one side of, the polygon,
/// within the box shrunk by pad, lies inside the child's side already.)
Aabb part_bounds(const ClippedPolygon& in_cell, const int cuts[3], int cut_count, int o, const Aabb& clip_box) {
    if (cut_count == 0) return in_cell.bounds_within(clip_box);
    const auto plane = [&](int a) { return (o >> a & 1) ? double(clip_box.lo[a]) : double(clip_box.hi[a]); };
    const ClippedPolygon* last_cut_of = &in_cell;
    ClippedPolygon part;
    if (cut_count > 1) {
        part.copy_from(in_cell);
        for (int j = 0; j + 1 < cut_count; ++j) part.keep_side(cuts[j], plane(cuts[j]), o >> cuts[j] & 1);
        last_cut_of = &part;
    }
    const int a = cuts[cut_count - 1];
    return last_cut_of->side_bounds_within(a, plane(a), o >> a & 1, clip_box);
}

}  // namespace

void split_reference(const SpatialRef& ref, const CornerTriples& triangles, const Aabb& cell, Vec3 planes, unsigned axes,
                     float pad, PartRule rule, ChildRefs& out) {
    // The sides of each cut axis the reference's box reaches (0 below, 1 above), and
    // the axes where it reaches both.
    int lo_side[3] = {0, 0, 0}, hi_side[3] = {0, 0, 0};
    int cuts[3], cut_count = 0;
    for (int a = 0; a < 3; ++a) {
        if (!(axes >> a & 1)) continue;
        const bool above = ref.box.hi[a] > planes[a];
        const bool below = ref.box.lo[a] < planes[a] || !above;
        lo_side[a] = below ? 0 : 1;
        hi_side[a] = above ? 1 : 0;
        if (below && above) cuts[cut_count++] = a;
    }
    out.count = 0;
    ClippedPolygon in_cell;  // the triangle clipped to the padded cell, once it is needed
    bool have_polygon = false;
    for (int z = lo_side[2]; z <= hi_side[2]; ++z)
        for (int y = lo_side[1]; y <= hi_side[1]; ++y)
            for (int x = lo_side[0]; x <= hi_side[0]; ++x) {
                const int o = x | y << 1 | z << 2;
                Aabb child = cell;
                for (int a = 0; a < 3; ++a) {
                    if (!(axes >> a & 1)) continue;
                    if (o >> a & 1) child.lo[a] = planes[a];
                    else child.hi[a] = planes[a];
                }
                // The reference's box holds its part grown by pad, so if it fits in child
                // grown by 2·pad, the part lies in child grown by pad: nothing to clip.
                const Aabb limit = padded(child, 2 * pad);
                Aabb box = ref.box;
                if (!limit.contains(ref.box)) {
                    if (rule == PartRule::BoxOverlap) {
                        box = intersection(ref.box, limit);
                    } else {
                        if (!have_polygon) {
                            const std::array<Vec3, 3>& corners = triangles[ref.tri];
                            in_cell = ClippedPolygon::of_triangle(corners[0], corners[1], corners[2]);
                            in_cell.clip_to(padded(cell, pad));
                            have_polygon = true;
                        }
                        const Aabb bounds = part_bounds(in_cell, cuts, cut_count, o, padded(child, pad));
                        if (bounds.empty()) continue;
                        // Never grow beyond what the parent had (clipping is monotone; this absorbs rounding).
                        box = intersection(padded(bounds, pad), ref.box);
                    }
                    if (box.empty()) continue;
                }
                out.child[out.count] = uint8_t(o);
                out.ref[out.count] = {ref.tri, box};
                ++out.count;
            }
}

namespace {

using Xyz = OctantSplit::Xyz;

Xyz xyz(Vec3 p) { return {{p.x, p.y, p.z, 0.0f}}; }

/// The axes where p is at most q: bit k set where p.v[k] <= q.v[k], for k = 0, 1, 2.
inline uint32_t axes_at_most(const Xyz& p, const Xyz& q) {
#if defined(__SSE2__)
    return uint32_t(_mm_movemask_ps(_mm_cmple_ps(_mm_load_ps(p.v), _mm_load_ps(q.v)))) & 7u;
#else
    return uint32_t(p.v[0] <= q.v[0]) | uint32_t(p.v[1] <= q.v[1]) << 1 | uint32_t(p.v[2] <= q.v[2]) << 2;
#endif
}

/// kOctantsOf[below | above << 3]: the octants (bit o for octant o) whose side of the
/// centre on each axis a is allowed: below if bit a of `below` is set, above if bit a
/// of `above` is (octant o lies above on axis a iff bit a of o is set).
constexpr std::array<uint8_t, 64> kOctantsOf = [] {
    std::array<uint8_t, 64> table{};
    for (uint32_t sides = 0; sides < 64; ++sides)
        for (uint32_t o = 0; o < 8; ++o) {
            bool allowed = true;
            for (uint32_t a = 0; a < 3; ++a) allowed = allowed && (sides >> ((o >> a & 1) * 3 + a) & 1);
            if (allowed) table[sides] |= uint8_t(1u << o);
        }
    return table;
}();

inline uint32_t octants_of(uint32_t below, uint32_t above) { return kOctantsOf[below | above << 3]; }

}  // namespace

OctantSplit::OctantSplit(const Aabb& cell, float pad, ClipMode mode)
    : exact_(mode == ClipMode::Exact), limit_(padded(cell, 2 * pad)), centre_(xyz(cell.center())) {
    // On axis a the octant spans [cell.lo, centre] or [centre, cell.hi]; grown as
    // padded() grows a box, so the same floats as padded(octant_box, ...).
    const float pad2 = 2 * pad;
    for (int side = 0; side < 2; ++side) {
        const Vec3 centre = this->centre();
        const Vec3 lo = side ? centre : cell.lo, hi = side ? cell.hi : centre;
        limit_lo_[side] = xyz(lo - Vec3{pad2, pad2, pad2});
        limit_hi_[side] = xyz(hi + Vec3{pad2, pad2, pad2});
        reach_lo_[side] = xyz(lo - Vec3{pad, pad, pad});
        reach_hi_[side] = xyz(hi + Vec3{pad, pad, pad});
    }
}

uint32_t OctantSplit::reached(const Aabb& box, const std::array<Vec3, 3>& corners) const {
    const Xyz lo = xyz(box.lo), hi = xyz(box.hi);
    // The sides the box reaches: above iff hi > centre, below iff lo < centre or not above.
    const uint32_t above = ~axes_at_most(hi, centre_) & 7u;
    const uint32_t below = (~axes_at_most(centre_, lo) | ~above) & 7u;
    // The box lies within the cell grown by 2·pad, so its part in an octant it reaches,
    // box ∩ (octant grown by 2·pad), is never empty: with Box, those octants are all.
    uint32_t reached = octants_of(below, above);
    if (!exact_) return reached;
    // With Exact, an octant holding the whole box holds the triangle's part; the others
    // need the triangle near them.
    uint32_t holds[2];
    for (int side = 0; side < 2; ++side) holds[side] = axes_at_most(limit_lo_[side], lo) & axes_at_most(hi, limit_hi_[side]);
    uint32_t to_test = reached & ~octants_of(holds[0], holds[1]);
    if (to_test == 0) return reached;
    // The octants holding a corner (grown by pad) are reached.
    for (const Vec3& corner : corners) {
        const Xyz p = xyz(corner);
        to_test &= ~octants_of(axes_at_most(reach_lo_[0], p) & axes_at_most(p, reach_hi_[0]),
                               axes_at_most(reach_lo_[1], p) & axes_at_most(p, reach_hi_[1]));
    }
    if (to_test == 0) return reached;
    const TriangleAxes triangle(corners[0], corners[1], corners[2]);
    for (uint32_t m = to_test; m; m &= m - 1) {
        const int o = __builtin_ctz(m);
        Aabb reach;
        for (int a = 0; a < 3; ++a) {
            reach.lo[a] = reach_lo_[o >> a & 1].v[a];
            reach.hi[a] = reach_hi_[o >> a & 1].v[a];
        }
        if (!triangle.overlaps(reach)) reached &= ~(1u << o);
    }
    return reached;
}

void add_split_notes(const SplitStops& stops, std::vector<std::string>& notes) {
    if (stops.leaves_at_depth_limit > 0) {
        std::ostringstream s;
        s << stops.leaves_at_depth_limit << " leaves stopped at the depth limit " << stops.depth_limit
          << " with more than leaf_size = " << stops.leaf_size << " references";
        notes.push_back(s.str());
    }
    if (stops.not_split > 0) {
        std::ostringstream s;
        s << stops.not_split << " " << stops.parts << " made leaves: " << stops.not_split_why;
        notes.push_back(s.str());
    }
    if (stops.budget_hit) {
        std::ostringstream s;
        s << "reference budget reached (" << stops.max_duplication << " x triangles): later " << stops.parts
          << " were made leaves instead of being split";
        notes.push_back(s.str());
    }
}

nlohmann::json partition_stats_json(const PartitionStats& s) {
    return {{"triangles", s.triangles},
            {"nodes", s.nodes},
            {"leaves", s.leaves},
            {"empty_leaves", s.empty_leaves},
            {"max_depth", s.max_depth},
            {"references", s.references},
            {"duplication", s.duplication},
            {"max_leaf_size", s.max_leaf_size},
            {"padding", s.padding},
            {"memory_bytes", s.memory_bytes},
            {"build_ms", s.build_ms},
            {"notes", s.notes}};
}

}  // namespace accelviz
