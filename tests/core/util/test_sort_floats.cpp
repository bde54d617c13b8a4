// sort_ascending: the KD tree's sort of box bounds gives std::sort's order, for small
// arrays (std::sort itself), mid-sized ones (8-bit digits) and big ones (11-bit digits),
// negative and special values included, and values sharing digits (passes skipped);
// sort_ascending_with_owners gives the same order and carries each value's owner along.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "core/util/random.h"
#include "core/util/sort_floats.h"

using namespace accelviz;

namespace {

/// Equal as floats (-0 == +0) and in the same order: the sweep's view of a sorted array.
void expect_sorted_like_std(std::vector<float> values) {
    std::vector<float> expected = values;
    std::sort(expected.begin(), expected.end());
    SortScratch scratch;
    sort_ascending(values, scratch);
    ASSERT_EQ(values.size(), expected.size());
    for (size_t i = 0; i < values.size(); ++i) ASSERT_EQ(values[i], expected[i]) << "position " << i;
}

/// sort_ascending_with_owners: the values in sort_ascending's order, each still with
/// its owner (owners start as 0..n-1, so owner k must point at a k-th value equal to it
/// bit for bit), and every owner once.
void expect_owners_follow(const std::vector<float>& values) {
    std::vector<float> sorted = values;
    std::vector<uint32_t> owners(values.size());
    for (size_t i = 0; i < owners.size(); ++i) owners[i] = uint32_t(i);
    std::vector<uint64_t> pairs, other;
    sort_ascending_with_owners(sorted, owners, pairs, other);
    std::vector<float> expected = values;
    std::sort(expected.begin(), expected.end());
    std::vector<bool> seen(values.size(), false);
    for (size_t i = 0; i < values.size(); ++i) {
        ASSERT_EQ(sorted[i], expected[i]) << "position " << i;
        ASSERT_LT(owners[i], values.size());
        ASSERT_FALSE(seen[owners[i]]) << "owner " << owners[i] << " twice";
        seen[owners[i]] = true;
        ASSERT_EQ(std::bit_cast<uint32_t>(sorted[i]), std::bit_cast<uint32_t>(values[owners[i]])) << "position " << i;
    }
}

}  // namespace

TEST(SortFloats, OwnersFollowTheirValuesInEverySize) {
    Rng rng(17);
    for (size_t n : {0, 1, 2, 63, 64, 65, 1000, 5000, 100000}) {
        SCOPED_TRACE(n);
        std::vector<float> values(n);
        for (float& v : values) v = rng.uniform(-1000.0f, 1000.0f);
        expect_owners_follow(values);
        // Ties, both zeros and values sharing their high digits (skipped passes).
        for (float& v : values) v = float(rng.next_u64() % 7) - 3.0f;
        for (size_t i = 0; i < n; i += 5) values[i] = -0.0f;
        expect_owners_follow(values);
        for (float& v : values) v = rng.uniform(1.0f, 1.001f);
        expect_owners_follow(values);
    }
}

TEST(SortFloats, BigAndSmallArraysSortAsStdSortDoes) {
    Rng rng(7);
    for (size_t n : {0, 1, 5, 31, 32, 33, 100, 1000, 2047, 2048, 2049, 10000, 100000}) {
        SCOPED_TRACE(n);
        std::vector<float> values(n);
        for (float& v : values) v = rng.uniform(-1000.0f, 1000.0f);
        expect_sorted_like_std(values);
    }
}

TEST(SortFloats, SignsZerosTiesAndExtremesKeepTheirOrder) {
    Rng rng(11);
    const float specials[] = {0.0f,
                              -0.0f,
                              1.0f,
                              -1.0f,
                              std::numeric_limits<float>::denorm_min(),
                              -std::numeric_limits<float>::denorm_min(),
                              std::numeric_limits<float>::max(),
                              std::numeric_limits<float>::lowest(),
                              std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity(),
                              1e-30f,
                              -1e30f};
    std::vector<float> values;
    for (int i = 0; i < 50000; ++i) values.push_back(specials[rng.next_u64() % std::size(specials)]);
    for (int i = 0; i < 50000; ++i) values.push_back(rng.uniform(-1.0f, 1.0f));
    expect_sorted_like_std(values);
}

TEST(SortFloats, ValuesSharingHighDigitsSortInEverySize) {
    // A small node's bounds often share sign and exponent: the passes of digits every
    // key shares are skipped, the others must still order them.
    Rng rng(13);
    for (size_t n : {40, 500, 3000}) {
        SCOPED_TRACE(n);
        std::vector<float> values(n);
        for (float& v : values) v = rng.uniform(1.0f, 1.001f);
        expect_sorted_like_std(values);
        for (float& v : values) v = -v;
        expect_sorted_like_std(values);
        std::vector<float> same(n, 2.5f);
        same[n / 2] = 2.5000002f;
        expect_sorted_like_std(same);
    }
}
