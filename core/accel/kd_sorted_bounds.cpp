#include "core/accel/kd_sorted_bounds.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "core/util/sort_floats.h"

namespace accelviz {

SortedBounds sort_bounds(const SpatialRefs& refs) {
    SortedBounds out;
    out.make(refs.size());
    const auto sort_list = [&](int k) {
        float* values = out.values.data() + size_t(k) * out.stride();
        uint32_t* owners = out.owners.data() + size_t(k) * out.stride();
        for (size_t i = 0; i < out.n; ++i) {
            values[i] = SortedBounds::bound(refs[i], k);
            owners[i] = uint32_t(i);
        }
        std::vector<uint64_t> pairs, other;
        sort_ascending_with_owners({values, out.n}, {owners, out.n}, pairs, other);
    };
    for_each_part(out.n, 6, sort_list);
    return out;
}

std::array<SortedBounds, 2> children_bounds(const SpatialRefs& parent, const SortedBounds& parent_bounds,
                                            const std::array<const SpatialRefs*, 2>& children,
                                            std::array<bool, 2> wanted) {
    // kept[c][i]: where parent reference i is in child c with its box unchanged, or
    // kNotKept (a reference may be kept in both: a thin box across the plane whose
    // parts' boxes, grown by the padding, are the whole box again).
    constexpr uint32_t kNotKept = UINT32_MAX;
    const size_t n = parent.size();
    if (parent_bounds.n != n) {  // the parent has no lists (not expected): the children's sorted from scratch
        std::array<SortedBounds, 2> sorted;
        for (size_t side = 0; side < 2; ++side)
            if (wanted[side]) sorted[side] = sort_bounds(*children[side]);
        return sorted;
    }
    std::array<std::vector<uint32_t>, 2> kept, cut;  // cut[c]: child c's references with a new box
    std::array<SortedBounds, 2> out;
    for (size_t side = 0; side < 2; ++side) {
        kept[side].assign(wanted[side] ? n : 0, kNotKept);
        if (!wanted[side]) continue;
        const SpatialRefs& child = *children[side];
        const size_t m = child.size();
        size_t j = 0;
        for (size_t i = 0; i < n && j < m; ++i) {
            if (child[j].tri != parent[i].tri) continue;
            if (std::memcmp(&child[j].box, &parent[i].box, sizeof(Aabb)) == 0) kept[side][i] = uint32_t(j);
            else cut[side].push_back(uint32_t(j));
            ++j;
        }
        if (j != m) {  // not the parent's references in order (not expected): sorted from scratch
            out[side] = sort_bounds(child);
            wanted[side] = false;
            kept[side].clear();
            continue;
        }
        out[side].make(m);
    }
    if (!wanted[0] && !wanted[1]) return out;
    const auto make_lists = [&](int k) {
        const float* values = parent_bounds.values.data() + size_t(k) * parent_bounds.stride();
        const uint32_t* owners = parent_bounds.owners.data() + size_t(k) * parent_bounds.stride();
        std::array<float*, 2> to_values;
        std::array<uint32_t*, 2> to_owners;
        for (size_t side = 0; side < 2; ++side)
            if (wanted[side]) {
                to_values[side] = out[side].values.data() + size_t(k) * out[side].stride();
                to_owners[side] = out[side].owners.data() + size_t(k) * out[side].stride();
            }
        // Each kept bound goes to its child's list, in order. No branch on whether it
        // is kept (a coin toss: about half go each way): every bound is written, and
        // the write position moves on only for a kept one (the list's spare slot takes
        // the last write).
        const auto filter = [&](size_t side) {
            float* list_values = to_values[side];
            uint32_t* list_owners = to_owners[side];
            const uint32_t* kept_as = kept[side].data();
            size_t w = 0;
            for (size_t p = 0; p < n; ++p) {
                const uint32_t to = kept_as[owners[p]];
                list_values[w] = values[p];
                list_owners[w] = to;
                w += to != kNotKept;
            }
            return w;
        };
        // Both children at once where both want lists: each bound read once.
        std::array<size_t, 2> kept_count = {0, 0};
        if (wanted[0] && wanted[1]) {
            const uint32_t *below_as = kept[0].data(), *above_as = kept[1].data();
            size_t wb = 0, wa = 0;
            for (size_t p = 0; p < n; ++p) {
                const uint32_t o = owners[p], tb = below_as[o], ta = above_as[o];
                const float v = values[p];
                to_values[0][wb] = v;
                to_owners[0][wb] = tb;
                wb += tb != kNotKept;
                to_values[1][wa] = v;
                to_owners[1][wa] = ta;
                wa += ta != kNotKept;
            }
            kept_count = {wb, wa};
        } else {
            for (size_t side = 0; side < 2; ++side)
                if (wanted[side]) kept_count[side] = filter(side);
        }
        for (size_t side = 0; side < 2; ++side) {
            if (!wanted[side]) continue;
            size_t from = kept_count[side];
            // The new bounds merged in from the back (the kept ones move up in place).
            const SpatialRefs& child = *children[side];
            std::vector<std::pair<float, uint32_t>> fresh(cut[side].size());
            for (size_t q = 0; q < fresh.size(); ++q)
                fresh[q] = {SortedBounds::bound(child[cut[side][q]], k), cut[side][q]};
            std::sort(fresh.begin(), fresh.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
            float* list_values = to_values[side];
            uint32_t* list_owners = to_owners[side];
            size_t dst = child.size(), f = fresh.size();
            while (f > 0) {
                --dst;
                if (from > 0 && fresh[f - 1].first < list_values[from - 1]) {
                    --from;
                    list_values[dst] = list_values[from];
                    list_owners[dst] = list_owners[from];
                } else {
                    --f;
                    list_values[dst] = fresh[f].first;
                    list_owners[dst] = fresh[f].second;
                }
            }
        }
    };
    for_each_part(n, 6, make_lists);
    return out;
}

}  // namespace accelviz
