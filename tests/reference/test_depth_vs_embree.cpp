// Our ray-cast depth (the values `render --depth-out` writes) against Embree's on
// the same camera-contract rays. Embree's watertight test and our Möller–Trumbore
// round differently, so a ray grazing an edge or a vertex may be given to the
// neighbouring triangle or slip through a crack on one side only; everywhere else
// the hit distance must agree to a few float ulps.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/cli/embree_reference.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "core/render/camera.h"
#include "core/render/ray_caster.h"

namespace accelviz {
namespace {

struct Agreement {
    size_t pixels = 0;
    size_t hit_by_both = 0;
    size_t hit_by_one = 0;        ///< a hit on one side, a miss on the other
    size_t t_disagrees = 0;       ///< both hit, |t - t_ref| > 1e-5 relative
    size_t beyond_1e6 = 0;        ///< both hit, |t - t_ref| > 1e-6 relative (grazing angles)
    double max_relative_error = 0;  ///< over pixels hit by both, excluding t_disagrees
};

/// The mesh scaled about the origin: the same picture at another size, to show no
/// absolute epsilon hides in the tests.
Mesh scaled(Mesh mesh, float factor) {
    for (Vec3& p : mesh.positions) p = p * factor;
    return mesh;
}

Agreement compare_with_embree(const Mesh& mesh, int width, int height) {
    const Camera camera(default_camera(mesh.bounds()), width, height);
    AccelConfig config;
    config.type = AccelType::Bvh;  // the default BVH: SAH binned, ordered (exact against brute force: tests/core/accel)
    auto accel = build_accelerator(mesh, config);
    EXPECT_TRUE(bool(accel));
    const Frame ours = ray_cast(**accel, mesh, camera, {.threads = 0});

    std::vector<Ray> rays;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) rays.push_back(camera.ray(x, y));
    cli::EmbreeReference embree(1);  // one thread: no spinning pool on a busy CI machine
    embree.build(mesh);
    cli::RayResults theirs(rays.size());
    embree.trace(rays, 1, theirs);

    Agreement a;
    a.pixels = rays.size();
    for (size_t i = 0; i < rays.size(); ++i) {
        const bool we_hit = std::isfinite(ours.depth[i]);
        const bool they_hit = theirs.tri[i] != Hit::kNoHit;
        if (we_hit != they_hit) { ++a.hit_by_one; continue; }
        if (!we_hit) continue;
        ++a.hit_by_both;
        const double rel = std::abs(double(ours.depth[i]) - double(theirs.t[i])) / double(theirs.t[i]);
        a.beyond_1e6 += rel > 1e-6;
        if (rel > 1e-5) ++a.t_disagrees;
        else a.max_relative_error = std::max(a.max_relative_error, rel);
    }
    std::printf("%s %dx%d: %zu pixels hit by both, %zu hit by one only, %zu differ on t by > 1e-5 and %zu by > 1e-6 (relative), max rel. error otherwise %.2e\n",
                mesh.name.c_str(), width, height, a.hit_by_both, a.hit_by_one, a.t_disagrees, a.beyond_1e6,
                a.max_relative_error);
    return a;
}

void expect_agreement(const Mesh& mesh, int width, int height) {
    const Agreement a = compare_with_embree(mesh, width, height);
    ASSERT_GT(a.hit_by_both, a.pixels / 20) << "the camera should see the mesh";
    // Edge and vertex grazers only: at most 1 pixel in 10,000.
    EXPECT_LE(a.hit_by_one, a.pixels / 10000 + 1);
    EXPECT_LE(a.t_disagrees, a.hit_by_both / 10000 + 1);
    // Almost everywhere within 1e-6 (8 float ulps); up to 4e-6 where the ray grazes
    // the triangle (cos < 0.1) and both computations of t lose digits (measured
    // against t in double precision: either side may be the closer one; ours is
    // Möller–Trumbore's dot(e2, q) / det, Embree's the plane equation).
    EXPECT_LE(a.beyond_1e6, a.hit_by_both / 200 + 1);
}

Mesh load(const std::string& source) {
    auto mesh = load_scene(source);
    EXPECT_TRUE(bool(mesh)) << (mesh ? std::string() : mesh.error());
    return mesh ? *mesh : Mesh{};
}

TEST(DepthVsEmbree, Bunny) {
    const std::string path = std::string(ACCELVIZ_SHARED_ASSETS) + "/bunny.obj";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not here";
    const Mesh bunny = load(path);
    expect_agreement(bunny, 640, 360);
}

TEST(DepthVsEmbree, BunnyAtThousandthAndThousandfoldScale) {
    const std::string path = std::string(ACCELVIZ_SHARED_ASSETS) + "/bunny.obj";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not here";
    const Mesh bunny = load(path);  // about 0.15 units across
    expect_agreement(scaled(bunny, 1e-3f), 320, 180);
    expect_agreement(scaled(bunny, 2e4f), 320, 180);  // about 3,000 units across
}

TEST(DepthVsEmbree, BuiltIns) {
    for (const char* source : {"builtin:teapot", "builtin:cornell", "builtin:sphere", "builtin:stadium"}) {
        SCOPED_TRACE(source);
        expect_agreement(load(source), 320, 180);
    }
}

}  // namespace
}  // namespace accelviz
