// "Draw with: ray cast": the 3D view's mesh drawn from the CPU ray caster's picture,
// its hit distances written to the z-buffer, shows what the rasterized mesh shows:
// the depth read back is the ray caster's t, the colours are the rasterized
// mesh's but for a few edge pixels, and the structure overlay is hidden behind the
// surface in the same places. "Auto" picks whichever is measured (or estimated)
// faster; the naive structure on a big view stays rasterized.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>

#include "app/gui/headless.h"
#include "app/gui/session.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "core/render/ray_caster.h"
#include "core/render/views.h"
#include "golden.h"

namespace accelviz {
namespace {

AppState teapot_state(DrawWith draw_with) {
    AppState state;
    state.scene = "builtin:teapot?n=4";
    state.view.draw_with = draw_with;
    return state;
}

/// The share of pixels whose colours differ by more than `tolerance` in a channel.
double differing_share(const Image& a, const Image& b, int tolerance) {
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    size_t differing = 0;
    for (size_t i = 0; i < std::min(a.pixels.size(), b.pixels.size()); ++i) {
        const Rgb p = a.pixels[i], q = b.pixels[i];
        if (std::abs(p.r - q.r) > tolerance || std::abs(p.g - q.g) > tolerance || std::abs(p.b - q.b) > tolerance)
            ++differing;
    }
    return double(differing) / double(std::max<size_t>(1, a.pixels.size()));
}

TEST(RayCastDraw, DepthReadBackIsTheRayCastersT) {
    AppState state = teapot_state(DrawWith::RayCast);
    state.view.show_bounds = false;
    state.overlay.show_structure = false;
    const int width = 200, height = 150;
    auto render = render_headless(state, WindowView::Structure, width, height);
    ASSERT_TRUE(render) << render.error();
    Frame gl_frame(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const size_t i = gl_frame.index(x, y);
            gl_frame.depth[i] = float(depth_to_ray_t(render->view, render->view_depth[i], x, y));
        }
    auto mesh = load_scene(state.scene);
    ASSERT_TRUE(mesh) << mesh.error();
    AccelConfig naive;
    naive.type = AccelType::Naive;
    auto accel = build_accelerator(*mesh, naive);
    ASSERT_TRUE(accel) << accel.error();
    const Frame ray = ray_cast(**accel, *mesh, Camera(render->view.camera, width, height));
    const DepthAgreement agreement = compare_depths(gl_frame, ray, 1e-4);
    EXPECT_GT(agreement.covered_by_both, size_t(width * height / 10));
    // The same rays, the same structure's answer: only the depth buffer's 24 bits round t.
    EXPECT_GE(agreement.agreeing_percent(), 99.9) << "max relative error " << agreement.max_relative_error;
    EXPECT_EQ(agreement.coverage_differs_percent(), 0.0);
}

TEST(RayCastDraw, PictureAndOverlayMatchTheRasterizedMesh) {
    // The teapot's BVH overlay: boxes in front of the surface are drawn, behind it hidden.
    for (const bool overlay : {false, true}) {
        AppState raster = teapot_state(DrawWith::Raster), cast = teapot_state(DrawWith::RayCast);
        raster.overlay.show_structure = cast.overlay.show_structure = overlay;
        auto a = render_headless(raster, WindowView::Structure, 320, 240);
        auto b = render_headless(cast, WindowView::Structure, 320, 240);
        ASSERT_TRUE(a && b);
        // Shading is the same formula (core/render/shading.h in both); pixels differ
        // where GL and the ray caster round a silhouette or a line's end differently.
        EXPECT_LT(differing_share(a->colour, b->colour, 24), 0.01) << "overlay " << overlay;
        EXPECT_GT(differing_share(a->colour, b->colour, 0), 0.0) << "the same picture twice: was it ray cast?";
    }
}

TEST(RayCastDraw, RayCastTeapotWithItsBvhMatchesGolden) {
    EXPECT_TRUE(testing::view_matches_golden(teapot_state(DrawWith::RayCast), WindowView::Gui, 640, 400,
                                             "teapot_gui_ray_cast"));
}

TEST(RayCastDraw, AutoChoosesTheFasterAndNaiveStaysRasterizedOnABigView) {
    auto app = HeadlessApp::create(320, 240);
    ASSERT_TRUE(app) << app.error();
    Session& session = (*app)->session();
    AppState state = teapot_state(DrawWith::Auto);
    auto loaded = load_and_build(state.scene, state.accel);
    ASSERT_TRUE(loaded) << loaded.error();
    session.set_scene(state, *loaded, false);
    FrameInput input;
    input.draw_ui = false;
    (*app)->draw(state, input);  // auto goes by the estimate: 3,552 triangles rasterize fast
    EXPECT_FALSE(session.mesh_ray_cast);
    session.raster_ms_per_triangle = 1.0;  // a rasterizer this slow: try the ray caster
    (*app)->draw(state, input);
    EXPECT_TRUE(session.mesh_ray_cast);
    // Measured times (the window's, bench-view's; golden images use the estimate alone).
    // The camera has long been still: every cast is of every pixel, so the measured
    // time is one full picture's and stays that (a slow machine that crossed the
    // stillness threshold between draws would otherwise swap a quarter picture's
    // estimate for a full one's mid-test).
    session.camera_moved_at = std::chrono::steady_clock::now() - std::chrono::seconds(60);
    input.wait_for_ray_cast = true;
    (*app)->draw(state, input);
    const double cast_ms = session.surface_cast.full_cast_milliseconds(session.scene_generation);
    EXPECT_GT(cast_ms, 0.0);
    ASSERT_TRUE(session.surface_cast.shown());
    EXPECT_EQ(session.surface_cast.shown()->divisor, 1) << "a full picture measured";
    EXPECT_TRUE(session.mesh_ray_cast) << "the cast, " << cast_ms << " ms, beats 3,552 ms of raster";
    const double triangles = double(session.scene->mesh->triangle_count());
    session.raster_ms_per_triangle = 0.9 * cast_ms / triangles;  // raster a little faster: not enough to switch
    (*app)->draw(state, input);
    EXPECT_TRUE(session.mesh_ray_cast);
    session.raster_ms_per_triangle = 0.5 * cast_ms / triangles;  // twice as fast: raster again
    (*app)->draw(state, input);
    EXPECT_FALSE(session.mesh_ray_cast);
    session.raster_ms_per_triangle = 1.1 * cast_ms / triangles;  // a little slower: it stays raster
    (*app)->draw(state, input);
    EXPECT_FALSE(session.mesh_ray_cast);
    input.wait_for_ray_cast = false;

    // Naive: the teapot at n = 40 (over 100,000 triangles) x 76,800 pixels is over the
    // budget; at n = 4 it is not.
    state.view.draw_with = DrawWith::RayCast;
    state.accel.type = AccelType::Naive;
    for (const auto& [scene, cast] : {std::pair{"builtin:teapot?n=4", true}, std::pair{"builtin:teapot?n=40", false}}) {
        state.scene = scene;
        auto naive = load_and_build(state.scene, state.accel);
        ASSERT_TRUE(naive) << naive.error();
        session.set_scene(state, *naive, false);
        (*app)->draw(state, input);
        EXPECT_EQ(session.mesh_ray_cast, cast) << scene;
        EXPECT_EQ(session.brute_force_cast_refused, !cast) << scene;
    }
    // Auto never chooses brute force, however slow the rasterizer, under the budget too.
    state.view.draw_with = DrawWith::Auto;
    state.scene = "builtin:teapot?n=4";
    auto small = load_and_build(state.scene, state.accel);
    ASSERT_TRUE(small) << small.error();
    session.set_scene(state, *small, false);
    session.raster_ms_per_triangle = 1.0;
    (*app)->draw(state, input);
    EXPECT_FALSE(session.mesh_ray_cast);
    EXPECT_FALSE(session.brute_force_cast_refused) << "auto chose: nothing refused";
}

}  // namespace
}  // namespace accelviz
