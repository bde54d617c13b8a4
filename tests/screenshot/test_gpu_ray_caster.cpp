// The GPU traversal (the compute shader over the binary BVH) against the CPU's: the
// same triangle and the same t per pixel on the scenes and cameras that break
// structures (slivers, equal boxes, a camera inside the mesh, most rays missing), the
// loop run as often as the CPU's walk visits nodes, and its heat map's golden image.
#include <filesystem>

#include <gtest/gtest.h>

#include "app/gl/gpu_ray_caster.h"
#include "app/gui/camera_control.h"
#include "app/platform/osmesa_context.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "core/render/ray_caster.h"
#include "core/render/views.h"
#include "golden.h"

namespace accelviz {
namespace {

struct Case {
    const char* scene;
    Vec3d eye_from_centre;  ///< in units of the box's extent (0: the centre, inside the mesh)
    double fov = 50;
};

TEST(GpuRayCaster, AgreesWithTheCpuPixelForPixelAndLoopsAsOftenAsItVisitsNodes) {
    auto context = OsMesaContext::create(1, 1);
    ASSERT_TRUE(context) << context.error();
    auto caster = GpuRayCaster::create();
    if (!caster && !gl.has_compute) GTEST_SKIP() << caster.error();
    ASSERT_TRUE(caster) << caster.error();
    const Case cases[] = {
        {"builtin:teapot", {0.6, 0.5, 1.4}},
        {"builtin:stadium", {0.3, 0.2, 0.6}},               // slivers at the lid's tip, a teapot in a big box
        {"builtin:stadium", {0.3, -0.49, 0.0}},             // 0.06 above the floor: its far rays graze it
        {"builtin:same-box?n=200", {0.8, 0.7, 1.2}},        // every box equal
        {"builtin:sphere?subdiv=3", {0.05, 0.02, 0.01}},    // from inside the sphere
        {"builtin:teapot", {4.0, 3.0, 6.0}, 20},            // far and narrow: most rays miss or graze
        {"builtin:kd-challenge", {0.5, 0.4, 1.5}},
        {"bunny.obj", {0.4, 0.3, 1.2}},                     // a scanned mesh (when ../shared is there)
        {"bunny.obj", {3.0, 2.0, 5.0}, 12},                 // mostly misses and grazing rays
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.scene);
        std::string source = c.scene;
        if (source.rfind("builtin:", 0) != 0) {
            source = std::string(ACCELVIZ_SHARED_ASSETS) + "/" + source;
            if (!std::filesystem::exists(source)) continue;
        }
        auto mesh = load_scene(source);
        ASSERT_TRUE(mesh) << mesh.error();
        AccelConfig config;
        config.type = AccelType::Bvh;
        auto accel = build_accelerator(*mesh, config);
        ASSERT_TRUE(accel) << accel.error();
        const Aabb box = mesh->bounds();
        const Vec3d centre = to_double(box.center()), extent = to_double(box.extent());
        CameraParams params;
        params.target = centre + Vec3d{0.01 * extent.x, 0.0, 0.0};
        params.eye = centre + Vec3d{c.eye_from_centre.x * extent.x, c.eye_from_centre.y * extent.y,
                                    c.eye_from_centre.z * extent.z};
        params.fov_deg = c.fov;
        const Camera camera(params, 160, 90);
        ASSERT_FALSE((*caster)->upload(*structure_if<Bvh>(**accel)));
        const GpuCast gpu = (*caster)->cast(camera);
        const Frame cpu = ray_cast(**accel, *mesh, camera, {.threads = 1, .count_work = true});
        const GpuAgreement agree = compare_with_cpu(gpu, cpu.tri, cpu.depth);
        EXPECT_GE(agree.same_share(), 0.9999) << agree.same_triangle << " of " << agree.pixels;
        EXPECT_LE(agree.max_relative_t, 1e-6);
        size_t hits = 0, same_visits = 0, same_tests = 0;
        for (size_t i = 0; i < gpu.tri.size(); ++i) {
            hits += gpu.tri[i] != Hit::kNoHit ? 1 : 0;
            same_visits += gpu.iterations[i] == cpu.nodes[i] ? 1 : 0;
            same_tests += gpu.tests[i] == cpu.tests[i] ? 1 : 0;
            EXPECT_LE(gpu.stack_depth[i], 64u);
        }
        EXPECT_GT(hits, 0u) << "the camera sees the mesh";
        EXPECT_EQ(same_visits, gpu.tri.size()) << "one loop iteration per node the CPU's walk visits";
        EXPECT_EQ(same_tests, gpu.tri.size()) << "the same triangle tests";
    }
}

TEST(GoldenImage, GpuLoopIterationsPerInvocation) {
    auto context = OsMesaContext::create(1, 1);
    ASSERT_TRUE(context) << context.error();
    auto caster = GpuRayCaster::create();
    if (!caster && !gl.has_compute) GTEST_SKIP() << caster.error();
    ASSERT_TRUE(caster) << caster.error();
    auto mesh = load_scene("builtin:teapot");
    ASSERT_TRUE(mesh);
    AccelConfig config;
    config.type = AccelType::Bvh;
    auto accel = build_accelerator(*mesh, config);
    ASSERT_TRUE(accel);
    ASSERT_FALSE((*caster)->upload(*structure_if<Bvh>(**accel)));
    CameraParams params = default_camera(mesh->bounds());
    frame_bounds(params, mesh->bounds(), 640.0 / 360.0);
    const GpuCast gpu = (*caster)->cast(Camera(params, 640, 360));
    const Image image = heat_view(gpu.iterations, 640, 360, "GPU: loop iterations per invocation (bvh)", 0);
    EXPECT_TRUE(testing::matches_golden(image, "gpu_heat_loop_teapot"));
}

}  // namespace
}  // namespace accelviz
