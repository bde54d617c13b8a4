// sort_ascending: the KD tree's sort of box bounds gives std::sort's order, for small
// arrays (std::sort itself), mid-sized ones (8-bit digits) and big ones (11-bit digits),
// negative and special values included, and values sharing digits (passes skipped).
#include <gtest/gtest.h>

#include <algorithm>
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

}  // namespace

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
