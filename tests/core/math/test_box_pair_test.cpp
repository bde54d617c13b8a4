// The binary BVH's paired box test (one instruction sequence for a node's two
// children) against the scalar widened slab test, box by box (the intervals, and
// whether the walk keeps each box for a closest hit so far): hostile boxes (flat,
// empty, unbounded) and rays (±0 direction components, origins on the planes, where
// 0 · inf is NaN), for rays that start at or ahead of their origin and rays that may
// hit behind it.
#include <bit>
#include <cmath>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "core/math/box_pair_test.h"

using namespace accelviz;

namespace {

/// A BVH node's memory: a box, then two words the test must ignore.
struct alignas(32) Record {
    Aabb box;
    uint32_t first;
    uint32_t count;
};
static_assert(sizeof(Record) == 32);

/// Coordinates drawn from a few values, so origins land on planes and boxes go flat.
float coordinate(std::mt19937& rng) {
    static const float kValues[] = {-2.0f, -1.0f, -0.0f, 0.0f, 0.5f, 1.0f, 3.0f};
    std::uniform_int_distribution<int> pick(0, 9);
    const int k = pick(rng);
    if (k < 7) return kValues[k];
    return std::uniform_real_distribution<float>(-4.0f, 4.0f)(rng);
}

float direction_component(std::mt19937& rng) {
    std::uniform_int_distribution<int> pick(0, 5);
    switch (pick(rng)) {
    case 0: return 0.0f;
    case 1: return -0.0f;
    case 2: return 1e-30f;
    default: return std::uniform_real_distribution<float>(-1.0f, 1.0f)(rng);
    }
}

Record random_record(std::mt19937& rng) {
    Record r;
    for (int axis = 0; axis < 3; ++axis) {
        float lo = coordinate(rng), hi = coordinate(rng);
        if (rng() % 8 != 0 && lo > hi) std::swap(lo, hi);  // an eighth stay empty (lo > hi)
        if (rng() % 16 == 0) lo = -kInfinity, hi = kInfinity;
        r.box.lo[axis] = lo;
        r.box.hi[axis] = hi;
    }
    // Words whose bits are a NaN and an infinity as floats: the test must not read them.
    r.first = 0x7fc00001u;
    r.count = 0x7f800000u;
    return r;
}

/// Bit for bit (a zero's sign included: the events show it).
bool same(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

template <bool kMayStartBehind>
void expect_pairs_match_the_scalar_test(uint32_t seed) {
    std::mt19937 rng(seed);
    int differences = 0;
    for (int i = 0; i < 200000 && differences < 5; ++i) {
        alignas(64) Record pair[2] = {random_record(rng), random_record(rng)};
        Ray ray{{coordinate(rng), coordinate(rng), coordinate(rng)},
                {direction_component(rng), direction_component(rng), direction_component(rng)}};
        ray.t_min = kMayStartBehind ? -std::uniform_real_distribution<float>(0.0f, 5.0f)(rng)
                                    : (rng() % 2 ? 0.0f : std::uniform_real_distribution<float>(0.0f, 2.0f)(rng));
        ray.t_max = rng() % 4 == 0 ? kInfinity : std::uniform_real_distribution<float>(0.0f, 8.0f)(rng);
        const BoxTestRay box_ray(ray);
        const BoxPairTestRay<kMayStartBehind> pair_ray(box_ray);
        // The limit (the closest hit so far): none, any value, or exactly a box's entry.
        const SlabResult first = widened_slab_test<kMayStartBehind>(pair[0].box, box_ray, ray.t_min, ray.t_max);
        const int limit_kind = int(rng() % 3);
        const float limit = limit_kind == 0   ? kInfinity
                            : limit_kind == 1 ? std::uniform_real_distribution<float>(-1.0f, 6.0f)(rng)
                                              : first.t_enter;
        // The SIMD pair (without AVX2 the scalar one), and the scalar pair.
        const SlabPair result = widened_slab_test_pair(pair[0].box, pair[1].box, pair_ray, ray.t_min, ray.t_max, limit);
        const SlabPair scalar =
            scalar_slab_test_pair<kMayStartBehind>(pair[0].box, pair[1].box, box_ray, ray.t_min, ray.t_max, limit);
        if (result.kept >> 2 || scalar.kept >> 2) {
            ADD_FAILURE() << "kept has bits beyond the two boxes: " << result.kept << ", " << scalar.kept;
            ++differences;
        }
        const std::array<SlabResult, 2>& both = result.boxes;
        for (int k = 0; k < 2; ++k) {
            const SlabResult one = widened_slab_test<kMayStartBehind>(pair[k].box, box_ray, ray.t_min, ray.t_max);
            // The walk's rule: the interval is not empty and begins no later than the closest hit.
            const bool kept = one.t_enter <= one.t_exit && !(one.t_enter > limit);
            if (same(one.t_enter, both[k].t_enter) && same(one.t_exit, both[k].t_exit) &&
                kept == bool(result.kept >> k & 1) && same(one.t_enter, scalar.boxes[k].t_enter) &&
                same(one.t_exit, scalar.boxes[k].t_exit) && kept == bool(scalar.kept >> k & 1))
                continue;
            std::ostringstream s;
            s << "box " << k << " lo " << pair[k].box.lo.x << ' ' << pair[k].box.lo.y << ' ' << pair[k].box.lo.z
              << " hi " << pair[k].box.hi.x << ' ' << pair[k].box.hi.y << ' ' << pair[k].box.hi.z << ", ray o "
              << ray.origin.x << ' ' << ray.origin.y << ' ' << ray.origin.z << " d " << ray.dir.x << ' ' << ray.dir.y
              << ' ' << ray.dir.z << " [" << ray.t_min << ", " << ray.t_max << "]: scalar [" << one.t_enter << ", "
              << one.t_exit << "], pair [" << both[k].t_enter << ", " << both[k].t_exit << "], limit " << limit
              << ", kept " << kept << " / " << (result.kept >> k & 1);
            ADD_FAILURE() << s.str();
            ++differences;
        }
    }
}

}  // namespace

TEST(BoxPairTest, BothIntervalsAreTheScalarTestsForRaysAhead) { expect_pairs_match_the_scalar_test<false>(7); }

TEST(BoxPairTest, BothIntervalsAreTheScalarTestsForRaysThatMayHitBehind) {
    expect_pairs_match_the_scalar_test<true>(11);
}

// The cell walks make their triangle tests' BoxTestRay from the slab test's RayPrecomp,
// the BVH from the Ray: the two must be the same bits (±0 and tiny components included),
// or the own-box rule would differ between structures.
TEST(BoxTestRay, MadeFromRayPrecompIsMadeFromTheRay) {
    std::mt19937 rng(13);
    for (int i = 0; i < 100000; ++i) {
        const Ray ray{{coordinate(rng), coordinate(rng), coordinate(rng)},
                      {direction_component(rng), direction_component(rng), direction_component(rng)}};
        const BoxTestRay from_ray(ray), from_pre{RayPrecomp(ray)};
        for (int axis = 0; axis < 3; ++axis) {
            ASSERT_TRUE(same(from_ray.origin[axis], from_pre.origin[axis]));
            ASSERT_TRUE(same(from_ray.dir_inv[axis], from_pre.dir_inv[axis])) << "ray " << i << " axis " << axis;
            ASSERT_TRUE(same(from_ray.near_dir_inv[axis], from_pre.near_dir_inv[axis]));
            ASSERT_TRUE(same(from_ray.far_dir_inv[axis], from_pre.far_dir_inv[axis]));
            ASSERT_EQ(from_ray.near_plane[axis], from_pre.near_plane[axis]);
            ASSERT_EQ(from_ray.far_plane[axis], from_pre.far_plane[axis]);
        }
    }
}
