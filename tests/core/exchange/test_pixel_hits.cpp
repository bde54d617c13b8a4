// A student's per-pixel answers against brute force's: agreement, ties on shared
// edges, the pixels that differ, and clear errors for a malformed file.
#include <gtest/gtest.h>

#include "core/accel/factory.h"
#include "core/exchange/pixel_hits.h"
#include "core/geometry/scene.h"

namespace accelviz {
namespace {

std::shared_ptr<const Accelerator> bvh(const Mesh& mesh) {
    AccelConfig c;
    c.type = AccelType::Bvh;
    return *build_accelerator(mesh, c);
}

TEST(PixelHits, OurOwnAnswersAgreeAndATamperedOneIsListed) {
    const Mesh mesh = *load_scene("builtin:teapot", MeshCache::Skip);
    const Camera camera(default_camera(mesh.bounds()), 40, 30);
    const auto reference = bvh(mesh);
    std::vector<PixelHit> hits;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            const Hit h = reference->intersect_closest(camera.ray(x, y));
            hits.push_back({x, y, h.tri, h.found() ? h.t * (1.0f + 1e-6f) : 0.0f});  // another formula's rounding
        }
    PixelHitComparison cmp = compare_pixel_hits(hits, camera, mesh, *reference);
    EXPECT_EQ(cmp.pixels, 1200u);
    EXPECT_EQ(cmp.agree, 1200u);
    EXPECT_TRUE(cmp.differ.empty());

    size_t hit_pixel = 0;
    while (hits[hit_pixel].tri == Hit::kNoHit) ++hit_pixel;
    hits[hit_pixel].t *= 1.01f;                      // the right triangle, the wrong distance
    hits[0].tri = hits[0].tri == Hit::kNoHit ? 0 : Hit::kNoHit;  // a miss where there is a hit, or the reverse
    hits[0].t = 1.0f;
    cmp = compare_pixel_hits(hits, camera, mesh, *reference);
    ASSERT_EQ(cmp.differ.size(), 2u);
    EXPECT_EQ(cmp.differ[0].yours.x, 0);
    EXPECT_EQ(cmp.differ[1].yours.x, hits[hit_pixel].x);
    EXPECT_EQ(cmp.differ[1].right.tri, hits[hit_pixel].tri);
}

TEST(PixelHits, AnotherTriangleAtTheSameDistanceIsATieOnlyIfTheRayMeetsIt) {
    // Two triangles sharing the edge x = 0 in the plane z = 0; a third far away.
    Mesh mesh;
    mesh.positions = {{0, -1, 0}, {0, 1, 0}, {-1, 0, 0}, {1, 0, 0}, {5, 5, 0}, {6, 5, 0}, {5, 6, 0}};
    mesh.indices = {{0, 1, 2}, {0, 3, 1}, {4, 5, 6}};
    CameraParams params;
    params.eye = {0, 0, 2};
    params.target = {0, 0, 0};
    const Camera camera(params, 1, 1);  // the one pixel's ray goes through the shared edge
    const auto reference = bvh(mesh);
    const Hit right = reference->intersect_closest(camera.ray(0, 0));
    ASSERT_TRUE(right.found());
    const uint32_t other = right.tri == 0 ? 1 : 0;
    PixelHitComparison cmp = compare_pixel_hits({{0, 0, other, right.t}}, camera, mesh, *reference);
    EXPECT_EQ(cmp.agree, 1u);
    EXPECT_EQ(cmp.ties, 1u);
    cmp = compare_pixel_hits({{0, 0, 2, right.t}}, camera, mesh, *reference);  // the ray never meets triangle 2
    EXPECT_EQ(cmp.differ.size(), 1u);
}

TEST(PixelHits, ParsesTheCsvAndNamesTheBadLine) {
    auto hits = parse_pixel_hits("x,y,triangle,t\n0,0,5,1.5\n\n3,2,-1,inf\r\n", 4, 3);
    ASSERT_TRUE(hits.ok()) << hits.error();
    ASSERT_EQ(hits->size(), 2u);
    EXPECT_EQ((*hits)[0].tri, 5u);
    EXPECT_EQ((*hits)[0].t, 1.5f);
    EXPECT_EQ((*hits)[1].tri, Hit::kNoHit);
    auto error = [](const std::string& text) {
        auto h = parse_pixel_hits(text, 4, 3);
        return h.ok() ? std::string("(parsed)") : h.error();
    };
    EXPECT_EQ(error("0,0,1\n"), "line 1: expected x,y,triangle,t (4 fields), found 3");
    EXPECT_EQ(error("0,0,1,1\n4,0,1,1\n"), "line 2: pixel (4, 0) is outside the 4 x 3 image (--width, --height)");
    EXPECT_EQ(error("0,0,1,1\na,0,1,1\n"), "line 2: x and y must be whole numbers");
    EXPECT_EQ(error("0,0,-2,1\n"), "line 1: the triangle must be an id, or -1 for a miss");
    EXPECT_EQ(error("0,0,1,nan\n"), "line 1: t must be a finite number");
}

}  // namespace
}  // namespace accelviz
