// Rng: SplitMix64 against its published test vectors, and the helpers' ranges.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>

#include "core/util/random.h"

using namespace accelviz;

TEST(Rng, MatchesTheSplitMix64ReferenceOutput) {
    // The reference sequences of Vigna's splitmix64.c (and Java's SplittableRandom).
    Rng zero(0);
    EXPECT_EQ(zero.next_u64(), 0xe220a8397b1dcdafull);
    EXPECT_EQ(zero.next_u64(), 0x6e789e6aa1b965f4ull);
    EXPECT_EQ(zero.next_u64(), 0x06c45d188009454full);
    Rng seeded(1234567);
    EXPECT_EQ(seeded.next_u64(), 6457827717110365317ull);
    EXPECT_EQ(seeded.next_u64(), 3203168211198807973ull);
    EXPECT_EQ(seeded.next_u64(), 9817491932198370423ull);
}

TEST(Rng, CopiesContinueTheSameSequence) {
    Rng a(99);
    a.next_u64();
    Rng b = a;
    for (int i = 0; i < 10; ++i) EXPECT_EQ(a.next_u64(), b.next_u64());
}

TEST(Rng, UniformStaysInRangeAndCoversIt) {
    Rng rng(7);
    double lo_d = 1, hi_d = -1;
    float lo_f = 1, hi_f = -1;
    double sum = 0;
    constexpr int kDraws = 100000;
    for (int i = 0; i < kDraws; ++i) {
        const double d = rng.uniform(-1.0, 1.0);
        const float f = rng.uniform(-1.0f, 1.0f);
        ASSERT_TRUE(d >= -1.0 && d <= 1.0);
        ASSERT_TRUE(f >= -1.0f && f <= 1.0f);
        lo_d = std::min(lo_d, d), hi_d = std::max(hi_d, d);
        lo_f = std::min(lo_f, f), hi_f = std::max(hi_f, f);
        sum += d;
    }
    EXPECT_LT(lo_d, -0.999);
    EXPECT_GT(hi_d, 0.999);
    EXPECT_LT(lo_f, -0.999f);
    EXPECT_GT(hi_f, 0.999f);
    EXPECT_NEAR(sum / kDraws, 0.0, 0.01);
    Rng unit(3);
    for (int i = 0; i < 1000; ++i) {
        const double u = unit.next_unit_double();
        ASSERT_TRUE(u >= 0.0 && u < 1.0);
    }
}

TEST(Rng, BelowIsInRangeAndUnbiasedEnough) {
    Rng rng(11);
    int counts[6] = {};
    for (int i = 0; i < 60000; ++i) {
        const uint64_t k = rng.below(6);
        ASSERT_LT(k, 6u);
        ++counts[k];
    }
    for (int c : counts) EXPECT_NEAR(c, 10000, 400);
    EXPECT_EQ(rng.below(0), 0u);
    EXPECT_EQ(rng.below(1), 0u);
}

TEST(Rng, MulHighIsTheTop64BitsOfTheProduct) {
    EXPECT_EQ(Rng::mul_high(0, ~0ull), 0u);
    EXPECT_EQ(Rng::mul_high(1ull << 32, 1ull << 32), 1u);
    EXPECT_EQ(Rng::mul_high(~0ull, ~0ull), ~0ull - 1);  // (2^64-1)^2 = 2^128 - 2^65 + 1
    EXPECT_EQ(Rng::mul_high(0x123456789abcdef0ull, 0xfedcba9876543210ull), 0x121fa00ad77d7422ull);
}
