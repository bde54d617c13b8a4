#pragma once
/// The KD tree's SAH build keeps each node's box bounds sorted (kd_sah.h sweeps them).

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/accel/spatial_refs.h"

namespace accelviz {

/// A node's references' box bounds, each of the six lists (lo and hi on each axis)
/// sorted ascending, with the index in the node's references of the box each bound
/// came from. Wald and Havran 2006, section 4.3: sorted once where a subtree's build
/// starts, then each child's lists are its parent's filtered in order, with only the
/// new bounds of references the split cut (the straddlers) sorted and merged in. A
/// per-node radix sort is linear too; this saves its passes (a constant factor).
struct SortedBounds {
    size_t n = 0;                  ///< references; 0: the lists are not made (a node that sweeps has more than 32)
    std::vector<float> values;     ///< list k (2·axis, +1 for hi) at [k·stride(), k·stride() + n)
    std::vector<uint32_t> owners;  ///< owners[i]: the reference values[i] is a bound of

    /// One slot more than n a list: where children_bounds writes what it does not keep.
    size_t stride() const { return n + 1; }
    void make(size_t count) {
        n = count;
        values.resize(6 * stride());
        owners.resize(6 * stride());
    }
    bool made() const { return n > 0; }
    std::span<const float> list(int k) const { return {values.data() + size_t(k) * stride(), n}; }
    static float bound(const SpatialRef& r, int k) { return k % 2 ? r.box.hi[k / 2] : r.box.lo[k / 2]; }
};

/// The six lists of `refs` sorted from scratch (big nodes: the lists in parallel).
SortedBounds sort_bounds(const SpatialRefs& refs);

/// The children's sorted lists from their parent's, for the children with `wanted`
/// set (the others get none). children[c] holds the references split_references gave
/// child c from `parent`, in the parent's order and at most one per parent reference
/// (a node holds each triangle once), so one pass in step finds where each went. A
/// reference whose box the split left as it was keeps its place in every list: one
/// pass over each of the parent's lists hands each bound to its child, in order. The
/// others' new bounds (the straddlers', cut by the plane) are sorted and merged in.
/// A parent without lists, or children not made so, get theirs sorted from scratch.
std::array<SortedBounds, 2> children_bounds(const SpatialRefs& parent, const SortedBounds& parent_bounds,
                                            const std::array<const SpatialRefs*, 2>& children,
                                            std::array<bool, 2> wanted);

}  // namespace accelviz
