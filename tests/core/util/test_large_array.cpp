// LargeArrayAllocator: where the arrays start (the BVH's sibling pairs on one cache
// line, big blocks on huge-page boundaries), and that vectors using it behave.
#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <vector>

#include "core/accel/bvh.h"
#include "core/util/large_array.h"

using namespace accelviz;

namespace {

uintptr_t address(const void* p) { return reinterpret_cast<uintptr_t>(p); }

}  // namespace

TEST(LargeArray, BvhSiblingPairsStartCacheLinesForSmallAndHugeArrays) {
    for (size_t count : {size_t(3), size_t(1001), size_t(200'001)}) {  // 96 B, 32 KB, 6.4 MB
        std::vector<BvhNode, BvhNodeAllocator> nodes(count);
        EXPECT_EQ(address(&nodes[1]) % 64, 0u) << count << " nodes";
        for (size_t i : {size_t(0), size_t(2), count - 2, count - 1})  // odd indices start lines, even ones end them
            EXPECT_EQ(address(&nodes[i]) % 64, i % 2 == 1 ? 0u : 32u) << "node " << i << " of " << count;
    }
}

TEST(LargeArray, BigBlocksStartOnHugePageBoundaries) {
    std::vector<uint32_t, LargeArrayAllocator<uint32_t>> small(1000), big(1'000'000);
    EXPECT_EQ(address(small.data()) % 64, 0u);
    EXPECT_EQ(address(big.data()) % LargeArrayAllocator<uint32_t>::kHugePage, 0u);
}

TEST(LargeArray, VectorsGrowCopyAndKeepTheirValues) {
    std::vector<uint32_t, LargeArrayAllocator<uint32_t>> ids;
    for (uint32_t i = 0; i < 700'000; ++i) ids.push_back(i);  // crosses from small to huge blocks
    const auto copy = ids;
    ASSERT_EQ(copy.size(), 700'000u);
    EXPECT_EQ(std::accumulate(copy.begin(), copy.end(), uint64_t(0)), uint64_t(699'999) * 700'000 / 2);
    ids.resize(10);
    ids.shrink_to_fit();
    EXPECT_EQ(ids.back(), 9u);
}

TEST(LargeArray, PrefaultedVectorsHoldTheirValuesAtEverySize) {
    // Below and above the huge-page size, and sizes that end inside a 4 KiB page: the
    // pages are written before the elements are made, never beyond the block.
    for (size_t count : {size_t(1), size_t(1000), size_t(524'288), size_t(524'289), size_t(3'000'001)}) {
        auto ids = make_prefaulted<std::vector<uint32_t, LargeArrayAllocator<uint32_t>>>(count);
        ASSERT_EQ(ids.size(), count);
        EXPECT_EQ(ids.front(), 0u);
        EXPECT_EQ(ids.back(), 0u);
        if (count * sizeof(uint32_t) >= LargeArrayAllocator<uint32_t>::kHugePage) {
            EXPECT_EQ(address(ids.data()) % LargeArrayAllocator<uint32_t>::kHugePage, 0u);
        }
        std::iota(ids.begin(), ids.end(), 0u);
        const auto moved = std::move(ids);
        EXPECT_EQ(moved.back(), uint32_t(count - 1));
        const auto copy = moved;
        EXPECT_EQ(std::accumulate(copy.begin(), copy.end(), uint64_t(0)), uint64_t(count - 1) * count / 2);
    }
}
