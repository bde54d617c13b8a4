// The inside/outside slice: every sample's vote is inside_by_parity's at that point,
// the same through the BVH as through brute force and on one thread as on all; on a
// closed sphere the inside samples are the disc the plane cuts, and no vote splits.
#include <cmath>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "core/accel/factory.h"
#include "test_support.h"
#include "core/geometry/scene.h"
#include "core/query/inside.h"
#include "core/query/inside_slice.h"
#include "core/traversal/observers.h"

using namespace accelviz;

namespace {

using test::build_default;

}  // namespace

TEST(InsideSlice, EverySampleIsTheParityVoteAtItsPointThroughBvhAndBruteForce) {
    auto mesh = load_scene("builtin:teapot");
    ASSERT_TRUE(mesh);
    auto bvh = build_default(*mesh, AccelType::Bvh);
    auto naive = build_default(*mesh, AccelType::Naive);
    for (int axis = 0; axis < 3; ++axis) {
        const SliceSpec spec{.axis = axis, .fraction = 0.4f, .columns = 24, .rows = 17};
        auto a = inside_slice(*bvh, *mesh, spec);
        auto b = inside_slice(*naive, *mesh, spec);
        ASSERT_TRUE(a) << a.error();
        ASSERT_TRUE(b) << b.error();
        EXPECT_EQ(a->votes, b->votes) << "axis " << axis;
        EXPECT_EQ(a->rays, 3u * 24u * 17u);
        EXPECT_LT(a->triangle_tests, b->triangle_tests) << "the BVH tests fewer triangles than brute force";
        const Aabb box = mesh->bounds();
        EXPECT_FLOAT_EQ(a->position, box.lo[axis] + 0.4f * (box.hi[axis] - box.lo[axis]));
        const TriangleArray triangles = make_triangles(*mesh);
        for (int r = 0; r < spec.rows; r += 4)
            for (int c = 0; c < spec.columns; c += 3) {
                const Vec3 p = a->sample(c, r);
                EXPECT_FLOAT_EQ(p[axis], a->position);
                const InsideTest t = inside_by_parity(p, [&](const Ray& ray) {
                    NoObserver none;
                    return count_crossings_brute_force(triangles, ray, none);
                });
                EXPECT_EQ(a->votes[size_t(r) * 24 + size_t(c)], t.votes_inside) << c << "," << r;
            }
    }
}

TEST(InsideSlice, OneThreadGivesTheVotesOfAll) {
    auto mesh = load_scene("builtin:teapot");
    ASSERT_TRUE(mesh);
    auto bvh = build_default(*mesh, AccelType::Bvh);
    const SliceSpec spec{.axis = 1, .fraction = 0.55f, .columns = 40, .rows = 40};
    auto all = inside_slice(*bvh, *mesh, spec);
    tbb::task_arena one(1);
    Expected<InsideSlice> single = Error{"not run"};
    one.execute([&] { single = inside_slice(*bvh, *mesh, spec); });
    ASSERT_TRUE(all && single);
    EXPECT_EQ(all->votes, single->votes);
    EXPECT_EQ(all->nodes_visited, single->nodes_visited);
}

TEST(InsideSlice, AClosedSphereIsInsideOnItsDiscAndNoVoteSplits) {
    auto mesh = load_scene("builtin:sphere?subdiv=4");
    ASSERT_TRUE(mesh);
    auto bvh = build_default(*mesh, AccelType::Bvh);
    const SliceSpec spec{.axis = 2, .fraction = 0.5f, .columns = 64, .rows = 64};
    auto slice = inside_slice(*bvh, *mesh, spec);
    ASSERT_TRUE(slice) << slice.error();
    const Aabb box = mesh->bounds();
    const Vec3 centre = box.center();
    const float radius = 0.5f * box.extent().x;
    size_t inside = 0;
    for (int r = 0; r < spec.rows; ++r)
        for (int c = 0; c < spec.columns; ++c) {
            const uint8_t votes = slice->votes[size_t(r) * 64 + size_t(c)];
            EXPECT_TRUE(votes == 0 || votes == 3) << "a closed mesh: the rays agree";
            const Vec3 p = slice->sample(c, r) - centre;
            const float d = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
            // Away from the surface (the tessellation lies within 2% of the radius).
            if (d < 0.97f * radius) {
                EXPECT_EQ(votes, 3) << c << "," << r;
            }
            if (d > 1.01f * radius) {
                EXPECT_EQ(votes, 0) << c << "," << r;
            }
            inside += votes == 3 ? 1 : 0;
        }
    EXPECT_GT(inside, 1000u);
}

TEST(InsideSlice, ABadSpecOrAStructureThatCannotCountIsAnError) {
    auto mesh = load_scene("builtin:cube");
    ASSERT_TRUE(mesh);
    auto grid = build_default(*mesh, AccelType::Grid);
    auto bvh = build_default(*mesh, AccelType::Bvh);
    auto refused = inside_slice(*grid, *mesh, SliceSpec{});
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().find("naive or the binary BVH"), std::string::npos) << refused.error();
    EXPECT_FALSE(inside_slice(*bvh, *mesh, SliceSpec{.axis = 3}));
    EXPECT_FALSE(inside_slice(*bvh, *mesh, SliceSpec{.fraction = 1.5f}));
    EXPECT_FALSE(inside_slice(*bvh, *mesh, SliceSpec{.columns = 0}));
    std::atomic<bool> cancel{true};
    auto cancelled = inside_slice(*bvh, *mesh, SliceSpec{}, &cancel);
    ASSERT_FALSE(cancelled);
    EXPECT_EQ(cancelled.error(), "cancelled");
}
