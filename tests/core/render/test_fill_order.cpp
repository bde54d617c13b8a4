// The fill-order replay: the rasterizer's picture after k triangles is the picture
// of the first k triangles rasterized alone, and the counts are the rasterizer's own;
// the ray caster's after p pixels is the finished picture's first p pixels.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "core/render/fill_order.h"
#include "core/render/ray_caster.h"

using namespace accelviz;

namespace {

const Mesh& teapot() {
    static const Mesh mesh = *load_scene("builtin:teapot?n=4");
    return mesh;
}

Mesh first_triangles(const Mesh& mesh, size_t k) {
    Mesh part;
    part.positions = mesh.positions;
    part.indices.assign(mesh.indices.begin(), mesh.indices.begin() + long(k));
    return part;
}

}  // namespace

TEST(FillOrder, TheRasterAfterKTrianglesIsTheFirstKTrianglesRasterizedAlone) {
    const Mesh& mesh = teapot();
    const Camera camera(default_camera(mesh.bounds()), 96, 64);
    RasterStats stats;
    RasterHistory history;
    const Frame full = rasterize(mesh, camera, &stats, &history);
    ASSERT_EQ(history.writes_before.size(), mesh.triangle_count() + 1);
    for (size_t k : {size_t(0), size_t(1), size_t(57), mesh.triangle_count() / 2, mesh.triangle_count()}) {
        SCOPED_TRACE(k);
        RasterFillCounts counts;
        const Image replayed = raster_fill_image(history, mesh, camera, k, &counts);
        RasterStats alone_stats;
        const Frame alone = rasterize(first_triangles(mesh, k), camera, &alone_stats);
        EXPECT_EQ(replayed.pixels, alone.colour.pixels);
        EXPECT_EQ(counts.triangles, k);
        EXPECT_EQ(counts.depth_tests, alone_stats.fragments);
        EXPECT_EQ(counts.depth_writes, alone_stats.depth_writes);
        EXPECT_LE(counts.overwrites, counts.depth_writes);
    }
    RasterFillCounts all;
    EXPECT_EQ(raster_fill_image(history, mesh, camera, mesh.triangle_count(), &all).pixels, full.colour.pixels);
    EXPECT_EQ(all.depth_tests, stats.fragments);
    EXPECT_EQ(all.depth_writes, stats.depth_writes);
    // A teapot seen from outside: some triangles are drawn over by nearer ones later.
    EXPECT_GT(all.overwrites, 0u);
    EXPECT_EQ(all.depth_writes - all.overwrites, uint64_t(std::count_if(full.tri.begin(), full.tri.end(),
                                                                          [](uint32_t t) { return t != Hit::kNoHit; })))
        << "every write is a first write of its pixel or an overwrite (of another triangle)";
}

TEST(FillOrder, TheRayCastAfterPPixelsIsItsFirstPPixelsInRowOrder) {
    const Mesh& mesh = teapot();
    const Camera camera(default_camera(mesh.bounds()), 48, 32);
    AccelConfig config;
    config.type = AccelType::Bvh;
    auto accel = build_accelerator(mesh, config);
    ASSERT_TRUE(accel) << accel.error();
    const Frame frame = ray_cast(**accel, mesh, camera, {.count_work = true});
    const uint64_t p = 48 * 10 + 7;
    RayFillCounts counts;
    const Image image = ray_cast_fill_image(frame, p, &counts);
    uint64_t nodes = 0, tests = 0;
    for (uint64_t i = 0; i < image.pixels.size(); ++i) {
        EXPECT_EQ(image.pixels[i], i < p ? frame.colour.pixels[i] : kBackground) << i;
        if (i < p) nodes += frame.nodes[i], tests += frame.tests[i];
    }
    EXPECT_EQ(counts.pixels, p);
    EXPECT_EQ(counts.pixel_count, 48u * 32u);
    EXPECT_EQ(counts.nodes, nodes);
    EXPECT_EQ(counts.triangle_tests, tests);
}

TEST(FillOrder, AmountsAreTheShareRoundedDownAndAllAtTheEnd) {
    EXPECT_EQ(fill_amount(0.0, 100), 0u);
    EXPECT_EQ(fill_amount(-1.0, 100), 0u);
    EXPECT_EQ(fill_amount(0.333, 100), 33u);
    EXPECT_EQ(fill_amount(1.0, 100), 100u);
    EXPECT_EQ(fill_amount(2.0, 100), 100u);
    EXPECT_EQ(fill_amount(0.29f, 100), 29u) << "0.29f is 0.28999999...: still 29";
    EXPECT_EQ(fill_amount(0.29f, 3552), 1030u);
}
