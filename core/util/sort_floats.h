#pragma once
/// Sorting floats fast: the KD tree's SAH sweep sorts every node's box bounds.

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace accelviz {

/// Scratch for sort_ascending (kept across nodes: no allocation per node).
struct SortScratch {
    std::vector<uint32_t> keys, other;
};

/// Sorts `values` ascending. Big arrays by a radix sort (three passes of 11, 11 and 10
/// bits over the floats' bits made monotone: flip every bit of a negative float, the
/// sign bit of a positive one), small ones by std::sort. The order is std::sort's but
/// for -0 and +0, which compare equal (the KD sweep treats them as one value). No NaN.
/// Linear in n, so a KD build's sorts are O(N log N) in all instead of O(N log^2 N).
inline void sort_ascending(std::vector<float>& values, SortScratch& scratch) {
    constexpr size_t kRadixFrom = 2048;
    const size_t n = values.size();
    if (n < kRadixFrom) {
        std::sort(values.begin(), values.end());
        return;
    }
    std::vector<uint32_t>& keys = scratch.keys;
    std::vector<uint32_t>& other = scratch.other;
    keys.resize(n);
    other.resize(n);
    // One pass makes the keys and counts all three digits; each digit pass then places.
    constexpr int kShift[3] = {0, 11, 22};
    constexpr uint32_t kMask[3] = {0x7FF, 0x7FF, 0x3FF};
    uint32_t count[3][2049] = {};
    for (size_t i = 0; i < n; ++i) {
        const uint32_t bits = std::bit_cast<uint32_t>(values[i]);
        const uint32_t key = bits ^ ((bits >> 31) ? 0xFFFFFFFFu : 0x80000000u);
        keys[i] = key;
        for (int d = 0; d < 3; ++d) ++count[d][((key >> kShift[d]) & kMask[d]) + 1];
    }
    for (int d = 0; d < 3; ++d) {
        uint32_t* start = count[d];  // start[digit]: where the digit's keys begin
        for (uint32_t b = 1; b <= kMask[d] + 1; ++b) start[b] += start[b - 1];
        for (size_t i = 0; i < n; ++i) other[start[(keys[i] >> kShift[d]) & kMask[d]]++] = keys[i];
        keys.swap(other);
    }
    for (size_t i = 0; i < n; ++i) {
        const uint32_t key = keys[i];
        values[i] = std::bit_cast<float>(key ^ ((key >> 31) ? 0x80000000u : 0xFFFFFFFFu));
    }
}

}  // namespace accelviz
