#pragma once
/// The KD tree's SAH sweep over one node (Wald & Havran 2006, section 4: the
/// candidates are the references' box boundaries, swept in sorted order), shared by
/// the builder, which keeps the cheapest plane, and the construction stepper's
/// chart, which keeps them all: so the chart's cheapest plane is the tree's.

#include <cstddef>
#include <vector>

#include "core/accel/kd_tree.h"
#include "core/accel/spatial_refs.h"
#include "core/util/sort_floats.h"

namespace accelviz {

/// A box's surface area, in double as the build weighs it.
inline double kd_area(const Aabb& b) {
    const double x = double(b.hi.x) - b.lo.x, y = double(b.hi.y) - b.lo.y, z = double(b.hi.z) - b.lo.z;
    return 2.0 * (x * y + y * z + z * x);
}

/// References going below / above plane s on `axis` (see SpatialRef: below iff
/// box.lo < s, above iff box.hi > s; a box with neither — a point exactly on the
/// plane — goes below).
inline bool goes_below(const SpatialRef& r, int axis, float s) { return r.box.lo[axis] < s || !(r.box.hi[axis] > s); }
inline bool goes_above(const SpatialRef& r, int axis, float s) { return r.box.hi[axis] > s; }

/// Calls visit(axis, position, below, above, cost) for every candidate plane
/// strictly inside `box`, axis by axis, in increasing position: a boundary of a
/// reference's box. below = #{lo < s}, above = #{hi > s} (a reference lying in the
/// plane goes below); cost(s) = C_trav + C_isect · (A_below·N_below + A_above·N_above) / A,
/// times (1 - empty_bonus) when one side is empty. `los`, `his`, `scratch`: reused buffers.
template <class Visit>
void sweep_kd_sah(const std::vector<SpatialRef>& refs, const Aabb& box, const KdConfig& c, std::vector<float>& los,
                  std::vector<float>& his, SortScratch& scratch, Visit&& visit) {
    const size_t n = refs.size();
    const double node_area = kd_area(box);
    for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, d = (a + 2) % 3;
        const double e_b = double(box.hi[b]) - box.lo[b], e_d = double(box.hi[d]) - box.lo[d];
        const double cross_section = e_b * e_d, perimeter_half = e_b + e_d;
        los.resize(n);
        his.resize(n);
        for (size_t i = 0; i < n; ++i) {
            los[i] = refs[i].box.lo[a];
            his[i] = refs[i].box.hi[a];
        }
        sort_ascending(los, scratch);
        sort_ascending(his, scratch);
        // Sweep the candidates (the merged, sorted lo and hi values) upwards.
        size_t i_lo = 0, i_hi = 0;
        while (i_lo < n || i_hi < n) {
            const float s = i_hi >= n || (i_lo < n && los[i_lo] < his[i_hi]) ? los[i_lo] : his[i_hi];
            // Counts for this s: all lo < s were passed already; then consume values == s.
            const size_t below = i_lo;
            while (i_lo < n && los[i_lo] == s) ++i_lo;
            while (i_hi < n && his[i_hi] == s) ++i_hi;
            const size_t above = n - i_hi;
            if (!(s > box.lo[a] && s < box.hi[a])) continue;  // a plane on the boundary cuts nothing off
            // The children's areas, linear in s: 2·(e_b·e_c + (extent along a)·(e_b + e_c)).
            const double area_lower = 2.0 * (cross_section + (double(s) - box.lo[a]) * perimeter_half);
            const double area_upper = 2.0 * (cross_section + (double(box.hi[a]) - s) * perimeter_half);
            double cost = c.cost_trav + c.cost_isect * (area_lower * double(below) + area_upper * double(above)) /
                                            node_area;
            if (below == 0 || above == 0) cost *= 1.0 - c.empty_bonus;
            visit(a, s, below, above, cost);
        }
    }
}

}  // namespace accelviz
