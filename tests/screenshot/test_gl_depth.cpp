// The GL depth buffer, read back and turned into the ray distance t per pixel
// with the camera contract, agrees with the CPU ray caster (naive structure) on
// the foundation issue's bounds: >= 99.5% of the pixels both cover agree within
// 1e-4 relative, and coverage differs on <= 0.5% of all pixels.
#include <gtest/gtest.h>

#include "app/gui/headless.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "core/render/ray_caster.h"
#include "core/render/views.h"

namespace accelviz {
namespace {

struct DepthCase {
    const char* name;
    const char* scene;
    std::optional<CameraParams> camera;  ///< empty: the scene's default view
};

DepthAgreement gl_against_ray_caster(const DepthCase& c, int width, int height) {
    AppState state;
    state.scene = c.scene;
    state.camera = c.camera;
    state.view.show_bounds = false;
    auto gl_render = render_headless(state, WindowView::Structure, width, height);
    EXPECT_TRUE(gl_render) << gl_render.error();
    if (!gl_render) return {};
    const View3D& view = gl_render->view;
    EXPECT_EQ(view.rect.width, width);
    EXPECT_EQ(view.rect.height, height);

    // GL: window depth -> t along each pixel's contract ray.
    Frame gl_frame(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const size_t i = gl_frame.index(x, y);
            gl_frame.depth[i] = float(depth_to_ray_t(view, gl_render->view_depth[i], x, y));
        }

    // CPU: the same camera, one ray per pixel centre through the naive structure.
    auto mesh = load_scene(c.scene);
    EXPECT_TRUE(mesh) << mesh.error();
    if (!mesh) return {};
    AccelConfig naive;
    naive.type = AccelType::Naive;
    auto accel = build_accelerator(*mesh, naive);
    EXPECT_TRUE(accel) << accel.error();
    if (!accel) return {};
    const Frame ray = ray_cast(**accel, *mesh, Camera(view.camera, width, height));

    const DepthAgreement agreement = compare_depths(gl_frame, ray, 1e-4);
    EXPECT_GT(agreement.covered_by_both, size_t(width * height / 10)) << c.name << ": the scene should fill the view";
    EXPECT_GE(agreement.agreeing_percent(), 99.5)
        << c.name << ": max relative error " << agreement.max_relative_error;
    EXPECT_LE(agreement.coverage_differs_percent(), 0.5) << c.name;
    return agreement;
}

TEST(GlDepth, CubeDefaultViewAgreesWithRayCaster) {
    gl_against_ray_caster({"cube default view", "builtin:cube", std::nullopt}, 160, 120);
}

TEST(GlDepth, CubeCloseGrazingViewAgreesWithRayCaster) {
    // Close and oblique: faces seen at grazing angles, depth range wide, the
    // near plane close; the cube fills the view.
    CameraParams camera;
    camera.eye = {2.2, 0.4, 1.3};
    camera.target = {-0.3, -0.2, 0.1};
    camera.up = {0, 1, 0};
    camera.fov_deg = 60;
    gl_against_ray_caster({"cube grazing view", "builtin:cube", camera}, 200, 150);
}

TEST(GlDepth, NonSquareViewKeepsTheContractAspect) {
    // A wide view: the horizontal extent comes from the aspect ratio, as in the contract.
    CameraParams camera;
    camera.eye = {0.5, 1.5, 3.5};
    camera.target = {0, 0, 0};
    camera.fov_deg = 30;
    gl_against_ray_caster({"cube wide view", "builtin:cube", camera}, 240, 90);
}

}  // namespace
}  // namespace accelviz
