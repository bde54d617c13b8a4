#pragma once
/// Sorting floats fast: the KD tree's SAH sweeps sorted box bounds (the build sorts
/// them where a subtree starts, the construction stepper's chart for every node it shows).

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace accelviz {

/// Scratch for sort_ascending (kept across the sorts of a chart: no allocation per sort).
struct SortScratch {
    std::vector<uint32_t> keys, other;
};

/// A float's bits made monotone as an unsigned key: every bit of a negative float
/// flipped, the sign bit of a positive one (-0 sorts just before +0).
inline uint32_t float_sort_key(float value) {
    const uint32_t bits = std::bit_cast<uint32_t>(value);
    return bits ^ ((bits >> 31) ? 0xFFFFFFFFu : 0x80000000u);
}
inline float float_from_sort_key(uint32_t key) {
    return std::bit_cast<float>(key ^ ((key >> 31) ? 0x80000000u : 0xFFFFFFFFu));
}

/// A least-significant-digit radix sort of `values` by kDigits digits of the widths
/// kBits (one pass counts every digit, then one placing pass per digit). A digit that
/// all keys share (often the sign and exponent in a small node) is not placed.
template <int kDigits, int... kBits>
void radix_sort_floats(std::vector<float>& values, SortScratch& scratch) {
    constexpr int kWidth[kDigits] = {kBits...};
    int shift[kDigits];
    for (int d = 0, s = 0; d < kDigits; s += kWidth[d], ++d) shift[d] = s;
    constexpr size_t kMaxBuckets = size_t(1) << std::max({kBits...});
    const size_t n = values.size();
    if (n == 0) return;
    std::vector<uint32_t>& keys = scratch.keys;
    std::vector<uint32_t>& other = scratch.other;
    keys.resize(n);
    other.resize(n);
    uint32_t count[kDigits][kMaxBuckets + 1] = {};
    for (size_t i = 0; i < n; ++i) {
        const uint32_t key = float_sort_key(values[i]);
        keys[i] = key;
        for (int d = 0; d < kDigits; ++d) ++count[d][((key >> shift[d]) & ((1u << kWidth[d]) - 1)) + 1];
    }
    for (int d = 0; d < kDigits; ++d) {
        const uint32_t mask = (1u << kWidth[d]) - 1;
        uint32_t* start = count[d];  // start[digit]: where the digit's keys begin
        if (start[((keys[0] >> shift[d]) & mask) + 1] == n) continue;  // one digit value: order unchanged
        for (uint32_t b = 1; b <= mask + 1; ++b) start[b] += start[b - 1];
        for (size_t i = 0; i < n; ++i) other[start[(keys[i] >> shift[d]) & mask]++] = keys[i];
        keys.swap(other);
    }
    for (size_t i = 0; i < n; ++i) values[i] = float_from_sort_key(keys[i]);
}

/// Sorts `values` ascending: by a radix sort over the floats' bits made monotone
/// (float_sort_key), with four 8-bit digits for arrays of up to 2047 values (small
/// count tables) and three digits of 11, 11 and 10 bits above; tiny arrays by
/// std::sort. The order is std::sort's but for -0 and +0, which compare equal (the KD
/// sweep treats them as one value). No NaN. Linear in n, and free of the comparison
/// sort's mispredicted branches.
inline void sort_ascending(std::vector<float>& values, SortScratch& scratch) {
    constexpr size_t kRadixFrom = 32, kWideDigitsFrom = 2048;
    const size_t n = values.size();
    if (n < kRadixFrom) {
        std::sort(values.begin(), values.end());
    } else if (n < kWideDigitsFrom) {
        radix_sort_floats<4, 8, 8, 8, 8>(values, scratch);
    } else {
        radix_sort_floats<3, 11, 11, 10>(values, scratch);
    }
}


/// Sorts `values` ascending as sort_ascending does, and `owners` (one per value) along
/// with them: afterwards owners[i] is the owner of values[i]. A least-significant-digit
/// radix sort of (key, owner) pairs by the key alone (three digits of 11, 11 and 10
/// bits; std::sort of the pairs below 64 values). `pairs`, `other`: scratch.
inline void sort_ascending_with_owners(std::span<float> values, std::span<uint32_t> owners,
                                       std::vector<uint64_t>& pairs, std::vector<uint64_t>& other) {
    const size_t n = values.size();
    pairs.resize(n);
    for (size_t i = 0; i < n; ++i) pairs[i] = uint64_t(float_sort_key(values[i])) << 32 | owners[i];
    if (n < 64) {
        std::sort(pairs.begin(), pairs.end());
    } else {
        other.resize(n);
        constexpr int kShift[3] = {32, 43, 54}, kWidth[3] = {11, 11, 10};
        for (int d = 0; d < 3; ++d) {
            const uint64_t mask = (uint64_t(1) << kWidth[d]) - 1;
            std::vector<uint32_t> start(size_t(mask) + 2, 0);
            for (size_t i = 0; i < n; ++i) ++start[((pairs[i] >> kShift[d]) & mask) + 1];
            if (start[((pairs[0] >> kShift[d]) & mask) + 1] == n) continue;  // one digit value: order unchanged
            for (size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
            for (size_t i = 0; i < n; ++i) other[start[(pairs[i] >> kShift[d]) & mask]++] = pairs[i];
            pairs.swap(other);
        }
    }
    for (size_t i = 0; i < n; ++i) {
        values[i] = float_from_sort_key(uint32_t(pairs[i] >> 32));
        owners[i] = uint32_t(pairs[i]);
    }
}

}  // namespace accelviz
