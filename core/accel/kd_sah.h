#pragma once
/// The KD tree's SAH sweep over one node (Wald & Havran 2006, section 4: the
/// candidates are the references' box boundaries, swept in sorted order), shared by
/// the builder, which keeps the cheapest plane, and the construction stepper's
/// chart, which keeps them all: so the chart's cheapest plane is the tree's.

#include <cstddef>
#include <span>
#include <vector>

#include "core/accel/kd_tree.h"
#include "core/accel/sah.h"
#include "core/accel/spatial_refs.h"
#include "core/util/sort_floats.h"

namespace accelviz {

/// With Möller–Trumbore the KD tree tests a leaf's triangles four at a time (its
/// leaves are kept as lanes: geometry/triangle_lanes.h), so its SAH counts a leaf's
/// tests, ceil(N / L) with L = KdConfig::leaf_lanes, where the lecture's formula has N
/// (as sah.h does for the wide BVH, and Embree's builders do).
inline double kd_tests(const KdConfig& c, size_t count) { return double(leaf_tests(count, uint64_t(c.leaf_lanes))); }

/// A box's surface area, in double as the build weighs it.
inline double kd_area(const Aabb& b) {
    const double x = double(b.hi.x) - b.lo.x, y = double(b.hi.y) - b.lo.y, z = double(b.hi.z) - b.lo.z;
    return 2.0 * (x * y + y * z + z * x);
}

/// The box's faces across `axis`: e_b·e_d and e_b + e_d (b, d the other two axes),
/// the parts of a child's area that do not depend on where the plane lies.
inline double kd_cross_section(const Aabb& box, int axis) {
    const int b = (axis + 1) % 3, d = (axis + 2) % 3;
    return (double(box.hi[b]) - box.lo[b]) * (double(box.hi[d]) - box.lo[d]);
}
inline double kd_perimeter_half(const Aabb& box, int axis) {
    const int b = (axis + 1) % 3, d = (axis + 2) % 3;
    return (double(box.hi[b]) - box.lo[b]) + (double(box.hi[d]) - box.lo[d]);
}

/// A_below·N_below + A_above·N_above of kd_split_cost (N counted in tests). The
/// children's areas are linear in s: 2·(cross_section + (extent along the axis)·perimeter_half).
inline double kd_weighted_area(const KdConfig& c, const Aabb& box, int axis, float s, size_t below, size_t above,
                               double cross_section, double perimeter_half) {
    const double area_lower = 2.0 * (cross_section + (double(s) - box.lo[axis]) * perimeter_half);
    const double area_upper = 2.0 * (cross_section + (double(box.hi[axis]) - s) * perimeter_half);
    return area_lower * kd_tests(c, below) + area_upper * kd_tests(c, above);
}

/// The SAH cost of splitting `box` at s on `axis` with `below` and `above` references:
/// C_trav + C_isect · (A_below·N_below + A_above·N_above) / A, times (1 - empty_bonus)
/// when one side is empty (N counted in tests, kd_tests). The children's areas are linear in s:
/// 2·(cross_section + (extent along the axis)·perimeter_half).
inline double kd_split_cost(const KdConfig& c, const Aabb& box, int axis, float s, size_t below, size_t above,
                            double cross_section, double perimeter_half, double node_area) {
    double cost = c.cost_trav +
                  c.cost_isect * kd_weighted_area(c, box, axis, s, below, above, cross_section, perimeter_half) /
                      node_area;
    if (below == 0 || above == 0) cost *= 1.0 - c.empty_bonus;
    return cost;
}

/// References going below / above plane s on `axis` (see SpatialRef: below iff
/// box.lo < s, above iff box.hi > s; a box with neither — a point exactly on the
/// plane — goes below).
inline bool goes_below(const SpatialRef& r, int axis, float s) { return r.box.lo[axis] < s || !(r.box.hi[axis] > s); }
inline bool goes_above(const SpatialRef& r, int axis, float s) { return r.box.hi[axis] > s; }

/// Calls visit(axis, position, below, above, cost) for every candidate plane on
/// `axis` strictly inside `box`, in increasing position: a boundary of a
/// reference's box. `los` and `his` are the node's references' box bounds on the axis,
/// each sorted ascending (-0 and +0 in either order). below = #{lo < s}, above =
/// #{hi > s} (a reference lying in the plane goes below); cost(s) = C_trav + C_isect ·
/// (A_below·N_below + A_above·N_above) / A, times (1 - empty_bonus) when one side is
/// empty. `stop()` true (asked first and every 65,536 candidates) ends the sweep early:
/// a node of millions of references sweeps for a good part of a second.
///
/// kCheaperOnly: visit only candidates that may cost less than every one visited before
/// (for a builder keeping the first cheapest). With both sides non-empty the cost is
/// C_trav + C_isect · W / A with W = A_below·N_below + A_above·N_above, and each IEEE
/// operation there is monotone in W: a candidate whose W is no lower than an earlier
/// such candidate's costs no less, so it is skipped before the division.
template <bool kCheaperOnly = false, class Visit, class Stop>
void sweep_sorted_kd_sah_axis(std::span<const float> los, std::span<const float> his, const Aabb& box,
                              const KdConfig& c, int a, Visit&& visit, Stop&& stop) {
    if (stop()) return;
    const size_t n = los.size();
    const double node_area = kd_area(box);
    const double cross_section = kd_cross_section(box, a), perimeter_half = kd_perimeter_half(box, a);
    double lowest_weighted_area = kInfinity;  // kCheaperOnly: the lowest W of a candidate with both sides non-empty
    // Sweep the candidates (the merged, sorted lo and hi values) upwards.
    size_t i_lo = 0, i_hi = 0;
    for (uint32_t step = 0; i_lo < n || i_hi < n; ++step) {
        if (step % 65536 == 0 && step > 0 && stop()) return;
        const float value = i_hi >= n || (i_lo < n && los[i_lo] < his[i_hi]) ? los[i_lo] : his[i_hi];
        // Counts for this s: all lo < s were passed already; then consume values == s.
        const size_t below = i_lo;
        while (i_lo < n && los[i_lo] == value) ++i_lo;
        while (i_hi < n && his[i_hi] == value) ++i_hi;
        const float s = value + 0.0f;  // -0 and +0 are one plane: +0, whichever the sort put first
        const size_t above = n - i_hi;
        if (!(s > box.lo[a] && s < box.hi[a])) continue;  // a plane on the boundary cuts nothing off
        if constexpr (kCheaperOnly) {
            if (below != 0 && above != 0) {
                const double weighted_area = kd_weighted_area(c, box, a, s, below, above, cross_section, perimeter_half);
                if (!(weighted_area < lowest_weighted_area)) continue;
                lowest_weighted_area = weighted_area;
            }
        }
        visit(a, s, below, above, kd_split_cost(c, box, a, s, below, above, cross_section, perimeter_half, node_area));
    }
}

/// sweep_sorted_kd_sah_axis over the references' bounds on `axis`, sorted here
/// (`los`, `his`, `scratch`: reused buffers). The construction stepper's chart sweeps
/// so; the build keeps its nodes' bounds sorted from the parent's (kd_sorted_bounds.h).
template <class Visit, class Stop>
void sweep_kd_sah_axis(const SpatialRefs& refs, const Aabb& box, const KdConfig& c, int a,
                       std::vector<float>& los, std::vector<float>& his, SortScratch& scratch, Visit&& visit,
                       Stop&& stop) {
    if (stop()) return;
    const size_t n = refs.size();
    los.resize(n);
    his.resize(n);
    for (size_t i = 0; i < n; ++i) {
        los[i] = refs[i].box.lo[a];
        his[i] = refs[i].box.hi[a];
    }
    if (stop()) return;
    sort_ascending(los, scratch);
    if (stop()) return;
    sort_ascending(his, scratch);
    sweep_sorted_kd_sah_axis(los, his, box, c, a, visit, stop);
}

/// The same, to the end.
template <class Visit>
void sweep_kd_sah_axis(const SpatialRefs& refs, const Aabb& box, const KdConfig& c, int a,
                       std::vector<float>& los, std::vector<float>& his, SortScratch& scratch, Visit&& visit) {
    sweep_kd_sah_axis(refs, box, c, a, los, his, scratch, visit, [] { return false; });
}

/// sweep_kd_sah_axis over the three axes in turn: every candidate plane of a node,
/// axis by axis, in increasing position.
template <class Visit>
void sweep_kd_sah(const SpatialRefs& refs, const Aabb& box, const KdConfig& c, std::vector<float>& los,
                  std::vector<float>& his, SortScratch& scratch, Visit&& visit) {
    for (int a = 0; a < 3; ++a) sweep_kd_sah_axis(refs, box, c, a, los, his, scratch, visit);
}

/// The cheapest plane of a node.
struct KdPlane {
    int axis = -1;  ///< -1: no candidate lies strictly inside the node
    float position = 0;
    double cost = kInfinity;
};

/// How many references a node may have for kd_cheapest_plane_by_counting.
inline constexpr size_t kKdCountingMax = 32;

/// The cheapest plane of sweep_kd_sah without sorting, for a node of at most
/// kKdCountingMax references: every candidate's counts are found by comparing it with
/// every reference (O(n²) compares over fixed-size arrays the compiler vectorises;
/// such a node needs no sorted bounds). Same candidates, same costs, and the same choice:
/// the first cheapest in the sweep's order (axis, then position).
template <size_t kLanes = kKdCountingMax>
KdPlane kd_cheapest_plane_by_counting(const SpatialRefs& refs, const Aabb& box, const KdConfig& c) {
    const size_t n = refs.size();
    if constexpr (kLanes > 8)  // fewer lanes for fewer references
        if (n <= kLanes / 2) return kd_cheapest_plane_by_counting<kLanes / 2>(refs, box, c);
    KdPlane best;
    if (n > kLanes) return best;
    const double node_area = kd_area(box);
    // Unused lanes never count: their lo is +inf (never < s), their hi -inf (never > s).
    alignas(32) float los[kLanes], his[kLanes];
    for (int a = 0; a < 3; ++a) {
        const double cross_section = kd_cross_section(box, a), perimeter_half = kd_perimeter_half(box, a);
        for (size_t i = 0; i < kLanes; ++i) {
            los[i] = i < n ? refs[i].box.lo[a] : kInfinity;
            his[i] = i < n ? refs[i].box.hi[a] : -kInfinity;
        }
        const auto consider = [&](float value) {
            const float s = value + 0.0f;  // as the sweep: +0 for -0
            if (!(s > box.lo[a] && s < box.hi[a])) return;
            uint32_t below = 0, above = 0;
            for (size_t j = 0; j < kLanes; ++j) {
                below += los[j] < s;
                above += his[j] > s;
            }
            const double cost = kd_split_cost(c, box, a, s, below, above, cross_section, perimeter_half, node_area);
            if (cost < best.cost || (cost == best.cost && a == best.axis && s < best.position)) best = {a, s, cost};
        };
        for (size_t i = 0; i < n; ++i) consider(los[i]);
        for (size_t i = 0; i < n; ++i) consider(his[i]);
    }
    return best;
}

}  // namespace accelviz
