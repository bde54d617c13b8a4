#include "app/gui/draw_frame.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key codes only: ImGui 1.86 indexes io.KeysDown by the GLFW backend's codes
#include <imgui.h>

#include "app/gl/texture.h"
#include "app/gl/view3d.h"
#include "app/gui/camera_control.h"
#include "app/gui/view_labels.h"
#include "app/gui/widget_audit.h"
#include "core/exchange/structure_file.h"
#include "core/render/colormap.h"
#include "core/render/views.h"

namespace accelviz {

namespace {

// [SECTION] Layout

/// Sidebar on the left, status bar at the bottom, the 3D view in the rest.
struct Layout {
    float sidebar_width = 0;
    float status_height = 0;
    ViewRect view;      ///< the whole area of the view (mouse and keys act here)
    ViewRect gl_view;   ///< where OpenGL draws the scene: `view`, or its left half when split
    ViewRect ray_view;  ///< split: the right half, the ray caster's picture (same size as gl_view)
    float right_panel_width = 0;  ///< a stepper's panel, the comparison or the two BVHs, right of the view (0: none)
};

/// Which panel sits right of the view (one at a time): a stepper's, the comparison, or
/// the two BVHs.
enum class RightPanel { None, Build, Stepper, Nearest, Comparison, TwoBvhs, Scaling };

/// `ui`: the sidebar and the status bar; `bottom_bar`: the height of lecture mode's
/// caption bar (instead of them). `right_panel`: a stepper's panel or the comparison, with or
/// without `ui`.
Layout compute_layout(int width, int height, bool ui, bool split, RightPanel right_panel, float bottom_bar = 0) {
    Layout layout;
    layout.status_height = std::floor(bottom_bar);
    const float font = ImGui::GetFontSize();
    if (ui) {
        layout.sidebar_width = std::floor(std::min(19.0f * font, 0.45f * float(width)));
        layout.status_height = std::floor(ImGui::GetTextLineHeight() + 2.0f * ImGui::GetStyle().FramePadding.y + 4.0f);
    }
    if (right_panel == RightPanel::Build)
        layout.right_panel_width =
            std::floor(std::min(30.0f * font, 0.6f * std::max(0.0f, float(width) - layout.sidebar_width)));
    else if (right_panel == RightPanel::Stepper || right_panel == RightPanel::Nearest)
        layout.right_panel_width = std::floor(std::min(26.0f * font, 0.4f * float(width)));
    else if (right_panel == RightPanel::Scaling)
        layout.right_panel_width =
            std::floor(std::min(32.0f * font, 0.5f * std::max(0.0f, float(width) - layout.sidebar_width)));
    else if (right_panel == RightPanel::Comparison || right_panel == RightPanel::TwoBvhs)
        // a table of 8 columns and a chart, or two pictures side by side: most of the width
        layout.right_panel_width =
            std::floor(std::min(42.0f * font, 0.65f * std::max(0.0f, float(width) - layout.sidebar_width)));
    const int left = int(layout.sidebar_width);
    const int right = int(layout.right_panel_width);
    layout.view = {left, 0, std::max(0, width - left - right), std::max(0, height - int(layout.status_height))};
    layout.gl_view = layout.view;
    if (split) {
        // Two halves of exactly the same size, so both renderers see the same camera.
        const int half = layout.view.width / 2;
        layout.gl_view = {layout.view.x, layout.view.y, half, layout.view.height};
        layout.ray_view = {layout.view.x + layout.view.width - half, layout.view.y, half, layout.view.height};
    }
    return layout;
}

constexpr ImGuiWindowFlags kFixedPanel = ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize |
                                         ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                                         ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoBringToFrontOnFocus;

// [SECTION] Lecture mode

/// The UI scale of lecture mode at least (text 32 px high: a projector's back row).
constexpr float kLectureUiScale = 2.0f;

void set_lecture_mode(Session& session, bool on) {
    session.lecture.on = on;
    session.lecture.blank = false;
}

/// "3/12  title" of the current preset and its caption on the next line (the
/// scene's name when none is current).
std::string lecture_caption(Session& session) {
    const int current = session.presets.current();
    if (current < 0) return session.scene ? session.scene->source : std::string();
    const PresetInfo& info = session.presets.entries()[size_t(current)];
    return std::to_string(current + 1) + "/" + std::to_string(session.presets.entries().size()) + "  " + info.title +
           (info.caption.empty() ? "" : "\n" + info.caption);
}

/// The caption bar's height for a frame `width` pixels wide: the caption wrapped to it.
float lecture_caption_height(Session& session, int width) {
    const ImGuiStyle& style = ImGui::GetStyle();
    const std::string text = lecture_caption(session);
    const float wrap = std::max(1.0f, float(width) - 2.0f * style.WindowPadding.x);
    const float text_height = ImGui::CalcTextSize(text.c_str(), nullptr, false, wrap).y;
    return std::ceil(std::max(text_height, ImGui::GetTextLineHeight()) + 2.0f * style.WindowPadding.y);
}

// [SECTION] Input for the 3D view

/// Mouse and keys move the camera, unless ImGui wants them (a panel is hovered
/// or a text field is being typed in).
void handle_view_input(AppState& state, Session& session, const Layout& layout) {
    const ViewRect& rect = layout.view;
    const ViewRect& gl_rect = layout.gl_view;
    const ImGuiIO& io = ImGui::GetIO();
    // The active stepper owns the arrow keys (the camera keeps the mouse and Shift+arrows;
    // the traversal stepper leaves Up / Down to the camera).
    const bool stepper_keys = state.build_step.active;
    const bool stepping = (state.stepper.open && state.stepper.ray.has_value()) || state.nearest.open;
    if (!io.WantCaptureKeyboard) session.build_stepper.handle_keys(state);
    if (!io.WantCaptureKeyboard && state.stepper.open) session.stepper.handle_keys(state);
    if (!io.WantCaptureKeyboard && state.nearest.open) session.nearest.handle_keys(state);

    if (!io.WantCaptureKeyboard) {
        if (ImGui::IsKeyPressed(GLFW_KEY_F1, false)) state.view.show_help = !state.view.show_help;
        if (ImGui::IsKeyPressed(GLFW_KEY_TAB, false)) state.view.show_ui = !state.view.show_ui;
        if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE, false)) {
            // Esc closes the help first; with no help open it cancels a load or build.
            if (state.view.show_help) state.view.show_help = false;
            else if (session.loader.busy()) session.loader.cancel();
        }
        if (ImGui::IsKeyPressed(GLFW_KEY_S, false)) state.view.mode = state.view.mode == ViewMode::Split ? ViewMode::View3D : ViewMode::Split;
        // Space plays the split view's fill order (the ray stepper, when open, owns Space).
        if (state.view.mode == ViewMode::Split && state.view.fill_order && !state.stepper.open && !state.nearest.open &&
            ImGui::IsKeyPressed(GLFW_KEY_SPACE, false))
            session.view_panel.play_or_pause_fill(state.view);
        // Presets in lecture order (a presentation clicker sends these keys).
        if (ImGui::IsKeyPressed(GLFW_KEY_PAGE_DOWN, false)) session.presets.step(+1, state, session);
        if (ImGui::IsKeyPressed(GLFW_KEY_PAGE_UP, false)) session.presets.step(-1, state, session);
        // Lecture mode: L in and out; B blanks the screen, C hides the caption bar, and
        // Home / End go to the first / last preset (unless a stepper owns them).
        if (ImGui::IsKeyPressed(GLFW_KEY_L, false)) set_lecture_mode(session, !session.lecture.on);
        // F12: this frame to the View panel's screenshot file (also in lecture mode, without panels).
        if (ImGui::IsKeyPressed(GLFW_KEY_F12, false)) session.screenshot_path = session.view_panel.screenshot_path;
        if (session.lecture.on) {
            if (ImGui::IsKeyPressed(GLFW_KEY_B, false)) session.lecture.blank = !session.lecture.blank;
            if (ImGui::IsKeyPressed(GLFW_KEY_C, false)) session.lecture.caption = !session.lecture.caption;
            const int presets = int(session.presets.entries().size());
            if (!state.stepper.open && !state.nearest.open && !state.build_step.active && presets > 0) {
                if (ImGui::IsKeyPressed(GLFW_KEY_HOME, false)) session.presets.load(0, state, session);
                if (ImGui::IsKeyPressed(GLFW_KEY_END, false)) session.presets.load(presets - 1, state, session);
            }
        }
    }
    if (!state.camera || rect.empty()) return;  // a preset may have just cleared the camera
    CameraParams& camera = *state.camera;
    const double aspect = gl_rect.height > 0 ? double(gl_rect.width) / gl_rect.height : 1.0;

    if (!io.WantCaptureKeyboard) {
        const double step = std::min(double(io.DeltaTime), 0.1);  // seconds; a stall must not spin the view
        const double turn = 1.5 * step;                            // radians per second held
        const double slide = 0.6 * step;                           // view heights per second held
        const bool shift = io.KeyShift;
        const double left = ImGui::IsKeyDown(GLFW_KEY_LEFT), right = ImGui::IsKeyDown(GLFW_KEY_RIGHT);
        const double up = ImGui::IsKeyDown(GLFW_KEY_UP), down = ImGui::IsKeyDown(GLFW_KEY_DOWN);
        if (shift)
            pan(camera, (right - left) * slide, (up - down) * slide);
        else if (stepping)
            orbit(camera, 0.0, (down - up) * turn);
        else if (!stepper_keys)
            orbit(camera, (left - right) * turn, (down - up) * turn);
        if (ImGui::IsKeyDown(GLFW_KEY_EQUAL) || ImGui::IsKeyDown(GLFW_KEY_KP_ADD)) dolly(camera, std::pow(0.3, step));
        if (ImGui::IsKeyDown(GLFW_KEY_MINUS) || ImGui::IsKeyDown(GLFW_KEY_KP_SUBTRACT))
            dolly(camera, std::pow(1.0 / 0.3, step));
        if (session.scene && ImGui::IsKeyPressed(GLFW_KEY_F, false)) frame_bounds(camera, session.scene->bounds, aspect);
        if (session.scene && ImGui::IsKeyPressed(GLFW_KEY_R, false)) {
            camera = default_camera(session.scene->bounds);
            frame_bounds(camera, session.scene->bounds, aspect);
        }
    }

    // A drag belongs to the view if it started there (it may then cross a panel).
    const bool hovered = !io.WantCaptureMouse && rect.contains(io.MousePos.x, io.MousePos.y);
    const bool any_down = ImGui::IsMouseDown(0) || ImGui::IsMouseDown(1) || ImGui::IsMouseDown(2);
    // The point light: a left drag that starts on its marker (in either half of the
    // split view: both have this camera and size) moves it in the plane facing the
    // camera, keeping its depth (the light follows the mouse).
    // (Moved by the mouse's motion in the plane facing the camera at the point's depth.)
    auto moved_with_mouse = [&](const Camera& cam, Vec3d p, double depth) {
        const double per_pixel = 2.0 * cam.tan_half_fov() * depth / gl_rect.height;
        return p + cam.right() * (io.MouseDelta.x * per_pixel) - cam.true_up() * (io.MouseDelta.y * per_pixel);
    };
    if (!ImGui::IsMouseDown(0) || !state.light.point_light() || !session.scene) session.dragging_light = false;
    if (state.light.point_light() && session.scene && !gl_rect.empty()) {
        const Camera cam(camera, gl_rect.width, gl_rect.height);
        const Vec3d light = light_position(state.light, session.scene->bounds);
        const Camera::ImagePoint at = cam.project(light);
        if (hovered && ImGui::IsMouseClicked(0) && at.depth > 0)
            for (const ViewRect& r : {gl_rect, layout.ray_view})
                if (!r.empty() && r.contains(io.MousePos.x, io.MousePos.y) &&
                    std::hypot(io.MousePos.x - r.x - at.x, io.MousePos.y - r.y - at.y) <=
                        light_marker_radius(state.view.ui_scale))
                    session.dragging_light = true;
        if (session.dragging_light) {
            if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) {  // a click alone leaves the light where it is
                const Vec3d moved = moved_with_mouse(cam, light, at.depth);
                if (within_max_coordinate(moved)) state.light.position = moved;
                // Cast as while the camera moves: a quarter of the pixels, so the shading keeps up.
                session.camera_moved_at = std::chrono::steady_clock::now();
            }
            return;
        }
    }
    // The nearest-point query point likewise (in the 3D view); while it moves, the
    // search's final state is shown, so the nearest point follows it.
    if (!ImGui::IsMouseDown(0) || !state.nearest.open || !state.nearest.point) session.dragging_query = false;
    if (state.nearest.open && state.nearest.point && !gl_rect.empty()) {
        const Camera cam(camera, gl_rect.width, gl_rect.height);
        const Camera::ImagePoint at = cam.project(*state.nearest.point);
        if (hovered && ImGui::IsMouseClicked(0) && at.depth > 0 && gl_rect.contains(io.MousePos.x, io.MousePos.y) &&
            std::hypot(io.MousePos.x - gl_rect.x - at.x, io.MousePos.y - gl_rect.y - at.y) <=
                light_marker_radius(state.view.ui_scale))
            session.dragging_query = true;
        if (session.dragging_query) {
            if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) {
                const Vec3d moved = moved_with_mouse(cam, *state.nearest.point, at.depth);
                if (within_max_coordinate(moved)) {
                    state.nearest.point = moved;
                    state.nearest.step = SIZE_MAX;  // the final state (NearestPanel::update clamps it)
                }
            }
            return;
        }
    }
    if (hovered && (ImGui::IsMouseClicked(0) || ImGui::IsMouseClicked(1) || ImGui::IsMouseClicked(2)))
        session.dragging_view = true;
    // The stepper open: a click (press and release without moving) picks the ray of
    // that pixel, in the 3D view or in the ray-cast half of the split view.
    if (state.stepper.open && session.dragging_view && ImGui::IsMouseReleased(0) &&
        io.MouseDragMaxDistanceSqr[0] < 9.0f) {
        const double mx = io.MouseClickedPos[0].x, my = io.MouseClickedPos[0].y;
        for (const ViewRect& r : {gl_rect, layout.ray_view})
            if (!r.empty() && r.contains(mx, my))
                StepperPanel::pick(state, camera, r.width, r.height, int(mx) - r.x, int(my) - r.y);
    }
    if (!any_down) session.dragging_view = false;
    if (session.dragging_view && (io.MouseDelta.x != 0 || io.MouseDelta.y != 0)) {
        const double dx = io.MouseDelta.x, dy = io.MouseDelta.y;
        const bool panning = ImGui::IsMouseDown(1) || ImGui::IsMouseDown(2) || io.KeyShift;
        if (panning)
            pan(camera, dx / rect.height, -dy / rect.height);  // the scene follows the mouse
        else
            orbit(camera, -dx * 0.008, dy * 0.008);  // drag right: the eye goes left around the target
    }
    if (hovered && io.MouseWheel != 0) dolly(camera, std::pow(0.85, double(io.MouseWheel)));
}

/// Split view, left half "opengl-depth": the mesh alone, opaque (what the z-buffer
/// of the lecture's loop holds); OpenGL's depth buffer read back, each value turned
/// into the ray distance t of that pixel's contract ray, and shown grey on the ray
/// cast's scale (its own range until the ray cast is there).
void draw_opengl_depth_as_grey(Session& session, Renderer& renderer, const View3D& view, const ViewRect& rect) {
    renderer.draw_mesh(session.mesh_for_raster(), MeshStyle{});
    Frame depth;
    depth.width = rect.width;
    depth.height = rect.height;
    depth.depth = depth_image_to_ray_t(view, renderer.read_depth(rect));
    float t_near = kInfinity, t_far = 0;
    if (const auto& shown = session.ray_cast.shown(); shown && shown->t_far > shown->t_near) {
        t_near = shown->t_near, t_far = shown->t_far;
    } else {
        for (float t : depth.depth)
            if (std::isfinite(t)) t_near = std::min(t_near, t), t_far = std::max(t_far, t);
    }
    if (!session.gl_depth_texture) session.gl_depth_texture = std::make_unique<Texture>();
    session.gl_depth_texture->upload(depth_grey_view(depth, t_near, t_far));
    renderer.draw_image(*session.gl_depth_texture, rect);
}

/// What a frame settles before it draws: the layout and the modes that shape it.
/// One right panel at a time: of the panels switched on, the one switched on in this
/// frame wins (the others are switched off); of several switched on at once (a preset),
/// the first in this order: the two BVHs, the comparison, the scaling chart, the ray
/// stepper, the nearest-point stepper, the construction stepper.
void keep_one_right_panel(AppState& state, Session& session) {
    const std::array<bool*, 6> open = {&state.two_bvhs.open, &state.comparison.open, &state.scaling.open,
                                       &state.stepper.open,  &state.nearest.open,    &state.build_step.active};
    std::array<bool, 6>& was_open = session.right_panel_was_open;
    const int panels = int(open.size());
    int keep = -1;
    for (int i = 0; i < panels && keep < 0; ++i)
        if (*open[i] && !was_open[i]) keep = i;
    for (int i = 0; i < panels && keep < 0; ++i)
        if (*open[i]) keep = i;
    for (int i = 0; i < panels; ++i) {
        if (i != keep) *open[i] = false;
        was_open[i] = *open[i];
    }
}

struct FramePlan {
    Layout layout;
    RightPanel right_panel = RightPanel::None;
    bool ui = false;        ///< panels and status bar drawn
    bool lecture = false;   ///< lecture mode: no panels; the caption bar and the view's labels
    bool split = false;     ///< raster | ray cast
    bool stepping = false;  ///< a ray is being stepped
    bool nearest = false;   ///< the nearest-point search is stepped (its panel is open)
    bool moving = false;         ///< the camera moves: the view is drawn lighter (Session::camera_moving)
    bool mesh_ray_cast = false;  ///< the CPU ray caster draws the mesh (Draw with)
    bool mesh_picture = false;   ///< ... and a picture of it is there to draw (none yet: no mesh)
};

// [SECTION] Draw with: raster or ray cast

/// Above this many triangle tests for a picture, brute force does not ray cast the
/// mesh (a picture would take minutes; the view stays rasterized).
constexpr double kBruteForceCastBudget = 2e9;
/// "Auto" tries the ray caster once a rasterized mesh is estimated slower than this.
constexpr double kAutoTryRayCastMs = 30.0;
/// Before any measurement: a software rasterizer's rate (llvmpipe, two cores:
/// about 12 million triangles a second, measured).
constexpr double kRasterTrianglesPerMs = 12e3;
/// A rate per triangle is learned only from meshes this big: a small mesh's time is
/// mostly the draw call's and glFinish's own, and scaled up to another scene it would
/// send a few thousand triangles to the ray caster.
constexpr size_t kRateFromTriangles = 100'000;

/// The estimated time of rasterizing the scene's mesh: as measured on it, else at
/// the rate measured on the last scene rasterized, else at a software renderer's.
double raster_estimate_ms(const Session& session) {
    if (session.raster_measured_scene == session.scene_generation && session.raster_mesh_ms > 0)
        return session.raster_mesh_ms;
    return double(session.scene->mesh->triangle_count()) *
           (session.raster_ms_per_triangle > 0 ? session.raster_ms_per_triangle : 1.0 / kRasterTrianglesPerMs);
}

/// How often auto measures the rasterized mesh again on the same scene (the view's
/// size and the machine's load change its time).
constexpr double kRasterRemeasureSeconds = 1.0;

/// "Auto" switches only to what is this much faster than what draws now (no flicker
/// between two close times).
constexpr double kAutoSwitchFactor = 0.8;

/// Whether the CPU ray caster draws the 3D view's mesh this frame (View > Draw with).
/// Not in the split view (its left half is the rasterizer to compare with), nor under
/// the construction stepper's picture, nor when the mesh is fully transparent.
/// `measured`: auto may go by measured times (not in golden images: the estimate alone).
/// A point light (shadows, reflections) needs rays: the mesh is then ray cast whatever
/// Draw with says (the rasterizer has the headlight only).
bool mesh_by_ray_cast(const AppState& state, Session& session, const FramePlan& plan, int pixels, bool measured) {
    session.brute_force_cast_refused = false;
    const bool needs_rays = state.light.point_light();
    if ((state.view.draw_with == DrawWith::Raster && !needs_rays) || plan.split || !session.scene || !session.scene->accel ||
        session.build_stepper.shows_3d(state) || state.overlay.mesh_opacity <= 0.0f)
        return false;
    const LoadedScene& scene = *session.scene;
    // Brute force answers the rays of the naive structure and of a structure file that
    // failed its check: #pixels x #triangles tests, never the faster way to draw.
    const bool brute_force = scene.accel_config.type == AccelType::Naive ||
                             (scene.structure_file && !scene.structure_file->check.valid());
    bool cast = true;
    if (state.view.draw_with == DrawWith::Auto && !needs_rays) {
        if (brute_force) return false;
        // Whichever draws this view faster, as last measured.
        const double cast_ms = measured ? session.surface_cast.full_cast_milliseconds(session.scene_generation) : 0;
        const double raster_ms = raster_estimate_ms(session);
        if (cast_ms <= 0) cast = raster_ms > kAutoTryRayCastMs;
        else cast = session.mesh_ray_cast ? !(raster_ms < kAutoSwitchFactor * cast_ms) : cast_ms < kAutoSwitchFactor * raster_ms;
    }
    if (cast && brute_force && double(scene.mesh->triangle_count()) * double(pixels) > kBruteForceCastBudget) {
        session.brute_force_cast_refused = true;
        return false;
    }
    return cast;
}

/// One right panel at a time, the layout, the 3D view's input (ImGui's capture flags are
/// from this frame's NewFrame), and the work this frame's picture needs started.
FramePlan plan_frame(AppState& state, Session& session, const FrameInput& input) {
    FramePlan plan;
    plan.lecture = input.draw_ui && session.lecture.on;
    plan.ui = input.draw_ui && state.view.show_ui && !plan.lecture;
    plan.split = state.view.mode == ViewMode::Split;
    const bool split = plan.split;
    keep_one_right_panel(state, session);
    // The construction stepper: its recorded build and chart (on workers; headless waits).
    session.build_stepper.update(state, session.scene, input.deterministic);
    const bool build_panel = session.build_stepper.has_panel(state, session.scene.get());
    plan.right_panel = build_panel              ? RightPanel::Build
                       : state.stepper.open     ? RightPanel::Stepper
                       : state.nearest.open     ? RightPanel::Nearest
                       : state.comparison.open  ? RightPanel::Comparison
                       : state.two_bvhs.open    ? RightPanel::TwoBvhs
                       : state.scaling.open     ? RightPanel::Scaling
                                                : RightPanel::None;
    const float caption_bar =
        plan.lecture && session.lecture.caption && !session.lecture.blank ? lecture_caption_height(session, input.width) : 0.0f;
    // Lecture mode keeps the right panel: a preset that steps a ray or a build, or compares
    // the structures, is about what that panel shows (the slab intervals, the SAH chart).
    plan.layout = compute_layout(input.width, input.height, plan.ui, split,
                                 plan.ui || plan.lecture ? plan.right_panel : RightPanel::None, caption_bar);
    plan.stepping = state.stepper.open && state.stepper.ray.has_value();
    plan.nearest = state.nearest.open;
    const Layout& layout = plan.layout;
    if (session.frame_pending && session.scene && state.camera && !layout.gl_view.empty()) {
        frame_bounds(*state.camera, session.scene->bounds, double(layout.gl_view.width) / layout.gl_view.height);
        session.frame_pending = false;
    }
    if (input.draw_ui) handle_view_input(state, session, layout);
    session.stepper.update(state, session, input.deterministic ? 0.0 : ImGui::GetIO().DeltaTime, input.deterministic);
    session.nearest.update(state, session, input.deterministic ? 0.0 : ImGui::GetIO().DeltaTime, input.deterministic);
    session.slice.update(state, session.scene, input.deterministic);
    session.view_panel.advance_fill(state.view, input.deterministic ? 0.0 : ImGui::GetIO().DeltaTime, split);
    // The comparison measures the rays of the 3D view's picture, while its panel is on
    // screen (headless waits for it).
    const bool comparison_shown = (plan.ui || plan.lecture) && plan.right_panel == RightPanel::Comparison;
    session.comparison.update(state, session.scene, layout.gl_view.width, layout.gl_view.height, comparison_shown,
                              input.deterministic);
    const bool two_bvhs_shown = (plan.ui || plan.lecture) && plan.right_panel == RightPanel::TwoBvhs;
    session.two_bvhs.update(state, session.scene, layout.gl_view.width, layout.gl_view.height, two_bvhs_shown,
                            input.deterministic);

    // Split view: the ray caster's picture of this frame's camera (on the worker;
    // headless waits for it so the frame is complete).
    if (split && session.scene && state.camera && !layout.ray_view.empty()) {
        const bool raster = state.view.left_view != LeftView::OpenGl || state.view.right_view == RightView::Depth ||
                            state.view.right_view == RightView::DepthDiff;
        session.ray_cast.request(session.scene, *state.camera, layout.ray_view.width, layout.ray_view.height,
                                 input.deterministic, raster, state.view.fill_order, state.light);
        session.ray_cast.update_texture(state.view);
    } else {
        // The split view is closed: a cast under way is not wanted. One that finished
        // (or stopped) is taken, or it would count as pending work for ever and the
        // window would never go idle.
        session.ray_cast.cancel();
        if (session.ray_cast.has_result()) session.ray_cast.update_texture(state.view);
    }

    // The camera's motion: a new camera now, or within the still time, draws lighter.
    // Golden images never move; bench-view's orbit does, as the window's would.
    const auto now = std::chrono::steady_clock::now();
    if ((state.camera && !(*state.camera == session.last_camera)) ||
        session.scene_generation != session.last_scene_generation) {
        if (state.camera) session.last_camera = *state.camera;
        session.last_scene_generation = session.scene_generation;
        session.camera_moved_at = now;
    }
    plan.moving = (!input.deterministic || input.wait_for_ray_cast) &&
                  std::chrono::duration<double>(now - session.camera_moved_at).count() < Session::kCameraStillSeconds;
    session.camera_moving = plan.moving;

    // Draw with: the mesh ray cast by the CPU (on the worker; headless waits for
    // the full picture, bench-view for the picture of each frame).
    plan.mesh_ray_cast = state.camera && !layout.gl_view.empty() &&
                         mesh_by_ray_cast(state, session, plan, layout.gl_view.width * layout.gl_view.height,
                                          !input.deterministic || input.wait_for_ray_cast);
    if (plan.mesh_ray_cast)
        session.surface_cast.request(session.scene, session.scene_generation, *state.camera, layout.gl_view.width,
                                     layout.gl_view.height, input.deterministic || input.wait_for_ray_cast,
                                     !plan.moving, state.light);
    else
        session.surface_cast.release();
    plan.mesh_picture = session.surface_cast.update_textures() && plan.mesh_ray_cast;
    session.mesh_ray_cast = plan.mesh_ray_cast;

    // Ray cast by GPU: the right half's shaded picture and heat maps from the compute
    // shader (UI thread: a new cast once the camera is still); depths stay the CPU's.
    const RightView right = state.view.right_view;
    session.gpu_cast_shown = false;
    session.gpu_cast_reason.clear();
    if (split && state.view.ray_cast_by == RayCastBy::Gpu && session.scene && state.camera && !layout.ray_view.empty()) {
        if (right == RightView::Depth || right == RightView::DepthDiff)
            session.gpu_cast_reason = "the depth views are the CPU's";
        else if (state.view.fill_order)
            session.gpu_cast_reason = "the fill order is the CPU's";
        else if (state.light.point_light())
            session.gpu_cast_reason = "it shades with the headlight only: no point light";
        else if (session.gpu_cast.update(state.view, session.scene, *state.camera, layout.ray_view.width,
                                         layout.ray_view.height, !plan.moving))
            session.gpu_cast_shown = true;
        else
            session.gpu_cast_reason = session.gpu_cast.error();
    } else {
        session.gpu_cast.release();  // the GPU's copy of a scene not shown
    }

    return plan;
}

/// The sidebar: scene, structure, stepper, view, construction and stats sections.
/// `dt`: seconds since the last frame, for the moving scene's Play (0: still).
void draw_sidebar(AppState& state, Session& session, const Layout& layout, int height, double dt) {
    ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(layout.sidebar_width, float(height) - layout.status_height),
                             ImGuiCond_Always);
    if (ImGui::Begin("##sidebar", nullptr, kFixedPanel)) {
        ImGui::TextDisabled("accelviz");
        session.scene_panel.draw(state, session, dt);
        session.structure_panel.draw(state, session);
        if (ImGui::CollapsingHeader("Stepper", ImGuiTreeNodeFlags_DefaultOpen)) {
            // Opening it makes the mesh translucent (once): the boxes a ray visits lie inside it.
            if (ImGui::Checkbox("Step one ray", &state.stepper.open) && state.stepper.open &&
                state.overlay.mesh_opacity >= 1.0f)
                state.overlay.mesh_opacity = 0.5f;
            if (state.stepper.open && !state.stepper.ray) {
                ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
                ImGui::TextWrapped("Click a pixel in the view to pick its ray.");
                ImGui::PopStyleColor();
            }
            if (ImGui::Checkbox("Nearest point to q", &state.nearest.open) && state.nearest.open &&
                state.overlay.mesh_opacity >= 1.0f)
                state.overlay.mesh_opacity = 0.5f;
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("The point of the mesh nearest to a point q, found through the BVH or the KD\n"
                                  "tree and stepped node by node: boxes outside the sphere of the best distance\n"
                                  "so far are skipped. Drag q in the view.");
        }
        if (ImGui::CollapsingHeader("Measure structures")) {
            ImGui::Checkbox("Measure every structure", &state.comparison.open);
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("Builds naive, grid, KD tree, octree and BVH on one thread and traces the same\n"
                                  "rays of this view through each: the lecture's comparison table, and when each\n"
                                  "build pays off.");
            ImGui::Checkbox("Frame time against triangles", &state.scaling.open);
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("The scene's mesh repeated 1, 2, 4, ... times up to millions of triangles, each\n"
                                  "scene rasterized (OpenGL and the CPU z-buffer) and ray cast through a structure:\n"
                                  "the lecture's last slide, measured on this machine, on log-log axes.");
            ImGui::Checkbox("Two BVHs side by side", &state.two_bvhs.open);
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("The scene's BVH made by two builders (median and SAH to start with), drawn side\n"
                                  "by side with their SAH costs and the nodes this view's rays visit: the lecture's\n"
                                  "\"two BVHs over the same triangles: which is better?\"");
        }
        session.view_panel.draw(state, session,
                                layout.view.height > 0 ? double(layout.view.width) / layout.view.height : 1.0);
        if (session.build_stepper.draw_sidebar(state, session.scene.get())) session.rebuild_structure(state);
        session.stats_panel.draw(state, session);
    }
    ImGui::End();
}

/// The right panel of a stepper: the construction stepper's or the ray stepper's.
void draw_right_panel(AppState& state, Session& session, const FrameInput& input, const FramePlan& plan) {
    const Layout& layout = plan.layout;
    if (plan.right_panel == RightPanel::Build)
        session.build_stepper.draw_panel(state, float(input.width) - layout.right_panel_width, 0,
                                         layout.right_panel_width, float(layout.view.height),
                                         layout.gl_view.height > 0 ? double(layout.gl_view.width) / layout.gl_view.height
                                                                   : 1.0);
    if (plan.right_panel == RightPanel::Stepper || plan.right_panel == RightPanel::Nearest ||
        plan.right_panel == RightPanel::Comparison || plan.right_panel == RightPanel::TwoBvhs ||
        plan.right_panel == RightPanel::Scaling) {
        ImGui::SetNextWindowPos(ImVec2(float(input.width) - layout.right_panel_width, 0), ImGuiCond_Always);
        ImGui::SetNextWindowSize(ImVec2(layout.right_panel_width, float(input.height) - layout.status_height),
                                 ImGuiCond_Always);
        if (plan.right_panel == RightPanel::Stepper) {
            if (ImGui::Begin("##stepper", nullptr, kFixedPanel)) session.stepper.draw(state, session, plan.lecture);
        } else if (plan.right_panel == RightPanel::Nearest) {
            if (ImGui::Begin("##nearest", nullptr, kFixedPanel)) session.nearest.draw(state, session, plan.lecture);
        } else if (plan.right_panel == RightPanel::Comparison) {
            if (ImGui::Begin("##comparison", nullptr, kFixedPanel))
                session.comparison.draw(ImGui::GetContentRegionAvail().x, plan.lecture);
        } else if (plan.right_panel == RightPanel::Scaling) {
            if (ImGui::Begin("##scaling", nullptr, kFixedPanel))
                session.scaling.draw(state, ImGui::GetContentRegionAvail().x, plan.lecture);
        } else if (ImGui::Begin("##two_bvhs", nullptr, kFixedPanel)) {
            session.two_bvhs.draw(state, ImGui::GetContentRegionAvail().x, plan.lecture);
        }
        ImGui::End();
    }
}

/// The panels around the 3D view and the labels over it.
void draw_panels(AppState& state, Session& session, const FrameInput& input, const FramePlan& plan) {
    const Layout& layout = plan.layout;
    const bool split = plan.split, stepping = plan.stepping;
    draw_sidebar(state, session, layout, input.height, input.deterministic ? 0.0 : ImGui::GetIO().DeltaTime);
    // The construction panel before the status bar, the stepper's after: the order the
    // windows were first drawn in (ImGui focuses the newest, and the construction
    // panel's title bar shows it).
    if (plan.right_panel == RightPanel::Build) draw_right_panel(state, session, input, plan);

    ImGui::SetNextWindowPos(ImVec2(0, float(input.height) - layout.status_height), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(float(input.width), layout.status_height), ImGuiCond_Always);
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding,
                        ImVec2(ImGui::GetStyle().WindowPadding.x, ImGui::GetStyle().FramePadding.y + 2.0f));
    if (ImGui::Begin("##status", nullptr, kFixedPanel | ImGuiWindowFlags_NoScrollbar))
        session.stats_bar.draw(state, session, input.frame_ms, input.deterministic);
    ImGui::End();
    ImGui::PopStyleVar();

    if (plan.right_panel == RightPanel::Stepper || plan.right_panel == RightPanel::Nearest ||
        plan.right_panel == RightPanel::Comparison || plan.right_panel == RightPanel::TwoBvhs ||
        plan.right_panel == RightPanel::Scaling)
        draw_right_panel(state, session, input, plan);
    // The overlay's legend: not over the CPU rasterizer's picture in the left half (it draws no overlay).
    const bool structure_legend =
        state.overlay.show_structure && !session.build_stepper.shows_3d(state) && !stepping && !plan.nearest &&
        !(split && (session.ray_cast.left_texture() || state.view.left_view == LeftView::OpenGlDepth));
    draw_view_labels(state, session, {layout.view, layout.gl_view, layout.ray_view, split}, structure_legend,
                     input.deterministic);
    session.help_window.draw(state);
}

/// Lecture mode's text: the right panel (a stepper's or the comparison), the view's own labels (titles, legends,
/// messages) and the caption bar with the preset's number, title and caption at the
/// bottom; with the caption bar hidden, the number alone in the view's bottom right corner.
void draw_lecture_labels(AppState& state, Session& session, const FrameInput& input, const FramePlan& plan) {
    if (session.lecture.blank) return;
    const Layout& layout = plan.layout;
    draw_right_panel(state, session, input, plan);
    const bool stepping = plan.stepping;
    draw_view_labels(state, session, {layout.view, layout.gl_view, layout.ray_view, plan.split},
                     state.overlay.show_structure && !stepping && !plan.nearest, input.deterministic);
    const int current = session.presets.current();
    const int count = int(session.presets.entries().size());
    constexpr ImGuiWindowFlags kBar = kFixedPanel | ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoInputs;
    if (session.lecture.caption && layout.status_height > 0) {
        ImGui::SetNextWindowPos(ImVec2(0, float(input.height) - layout.status_height), ImGuiCond_Always);
        ImGui::SetNextWindowSize(ImVec2(float(input.width), layout.status_height), ImGuiCond_Always);
        if (ImGui::Begin("##lecture_caption", nullptr, kBar)) {
            ImGui::PushTextWrapPos(float(input.width) - ImGui::GetStyle().WindowPadding.x);
            ImGui::TextUnformatted(lecture_caption(session).c_str());
            ImGui::PopTextWrapPos();
        }
        ImGui::End();
    }
    if (current >= 0 && !session.lecture.caption) {
        // The caption bar hidden: the number alone, bottom right of the view (where no
        // label of the view goes; a stepper's panel may take the screen's right side).
        char number[32];
        std::snprintf(number, sizeof number, "%d/%d", current + 1, count);
        const float margin = 0.5f * ImGui::GetFontSize();
        ImGui::SetNextWindowPos(ImVec2(float(layout.view.x + layout.view.width) - margin,
                                       float(layout.view.y + layout.view.height) - margin),
                                ImGuiCond_Always, ImVec2(1.0f, 1.0f));
        ImGui::SetNextWindowBgAlpha(0.6f);
        if (ImGui::Begin("##lecture_number", nullptr,
                         ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoInputs |
                             ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing))
            ImGui::TextUnformatted(number);
        ImGui::End();
    }
}

/// The GL picture: background, then the 3D view (mesh, structure or a stepper's
/// geometry), the split view's CPU images.
FrameLayout draw_scene(AppState& state, Renderer& renderer, Session& session, const FrameInput& input,
                       const FramePlan& plan) {
    const Layout& layout = plan.layout;
    const bool split = plan.split, stepping = plan.stepping;
    FrameLayout out;
    out.view_rect = layout.gl_view;
    if (plan.lecture && session.lecture.blank) {
        renderer.begin_frame(input.width, input.height, Rgb{0, 0, 0});
        session.view_cache.forget();  // no view: no picture under way (the window would keep drawing for it)
        return out;
    }
    renderer.begin_frame(input.width, input.height, state.view.background);
    if (session.scene && state.camera && !layout.gl_view.empty()) {
        session.upload_to_gpu(state.overlay);  // the panels may have changed the overlay
        out.view = make_view3d(*state.camera, layout.gl_view, session.scene->bounds);
        // A still view drawn from the settings alone: the picture kept from the last
        // frame, if nothing it was drawn from has changed (ViewCache).
        const bool build_step_3d = session.build_stepper.shows_3d(state);
        const bool keepable = !split && !stepping && !plan.nearest && !build_step_3d && !state.view.slice &&
                              !plan.moving && renderer.frame_copies_work();
        ViewCache::Key key;
        if (keepable) {
            key = {input.width, input.height, layout.gl_view, *state.camera, state.view, state.overlay, state.light,
                   session.scene_generation, plan.mesh_ray_cast,
                   plan.mesh_picture ? session.surface_cast.shown() : std::nullopt};
            if (session.view_cache.draw(key, renderer)) {
                out.scene_drawn = true;
                return out;
            }
        }
        renderer.begin_view(out.view);
        renderer.set_line_width(state.view.line_width);
        MeshStyle mesh_style;
        mesh_style.opacity = state.overlay.mesh_opacity;
        // While a ray or a nearest-point search is stepped, the step's own boxes replace
        // the whole structure's.
        const bool overlay = state.overlay.show_structure && !stepping && !plan.nearest;
        // A slow still view with more boxes than a frame should draw draws them a share
        // per frame (ViewCache): it starts a picture, or goes on with the one under way.
        ViewCache& cache = session.view_cache;
        const size_t boxes_total = overlay ? session.overlay_boxes->size() : 0;
        const ViewCache::Share share = cache.plan_frame(key, keepable, boxes_total, mesh_style.opacity >= 1.0f);
        auto draw_overlay = [&] {
            if (share.goes_on) {  // the picture so far holds the rest
                renderer.draw_boxes(*session.overlay_boxes, share.count, share.first);
                return;
            }
            if (state.view.show_bounds) renderer.draw_boxes(*session.bounds_buffer);
            if (stepping) session.stepper.draw_3d(renderer, state.view.line_width);
            if (plan.nearest) session.nearest.draw_3d(renderer, state.view.line_width);
            if (!overlay) return;
            const size_t budget = session.moving_boxes.boxes();
            renderer.draw_quads(*session.overlay_quads, plan.moving ? session.overlay.moving_quads(budget) : SIZE_MAX);
            renderer.draw_boxes(*session.overlay_boxes, plan.moving ? session.overlay.moving_prefix(budget) : share.count);
            if (plan.moving) session.moving_boxes.drew_moving();
        };
        const bool gl_depth_view = split && state.view.left_view == LeftView::OpenGlDepth;
        if (gl_depth_view) {
            draw_opengl_depth_as_grey(session, renderer, out.view, layout.gl_view);
        } else if (share.goes_on) {
            // A picture under way: the picture so far with the mesh's depth, then the next boxes.
            renderer.draw_image_with_depth(cache.picture(), cache.depth(), 1.0f, /*far_pixels=*/true);
            draw_overlay();
        } else if (build_step_3d) {
            // The construction stepper's picture replaces the structure overlay
            // (and the scene's bounds: the root's box is the first step's).
            session.build_stepper.draw_3d(renderer, session.mesh_for_raster(), state.build_step.step,
                                          state.view.background);
        } else {
            // The mesh: its triangles rasterized, or the ray caster's picture with its depth.
            auto draw_surface = [&] {
                if (plan.mesh_ray_cast) {
                    if (plan.mesh_picture)
                        renderer.draw_image_with_depth(session.surface_cast.colour(), session.surface_cast.depth(),
                                                       mesh_style.opacity);
                    return;
                }
                // Auto measures the rasterized mesh (to glFinish) to choose between the two,
                // on a new scene and then once in kRasterRemeasureSeconds: the two waits
                // split a software renderer's frame in three passes over the frame, a
                // quarter of a frame's time spent on every frame otherwise. The mesh's
                // upload (a new scene's first raster frame) is not part of it.
                const auto now = std::chrono::steady_clock::now();
                const bool measure =
                    state.view.draw_with == DrawWith::Auto && !input.deterministic &&
                    (session.raster_measured_scene != session.scene_generation ||
                     std::chrono::duration<double>(now - session.raster_measured_at).count() >= kRasterRemeasureSeconds);
                const MeshBuffer& mesh = session.mesh_for_raster();
                if (measure) renderer.finish();
                const auto start = std::chrono::steady_clock::now();
                renderer.draw_mesh(mesh, mesh_style);
                if (!measure) return;
                renderer.finish();
                session.raster_measured_at = std::chrono::steady_clock::now();
                session.raster_mesh_ms = std::chrono::duration<double, std::milli>(session.raster_measured_at - start).count();
                session.raster_measured_scene = session.scene_generation;
                const size_t triangles = session.scene->mesh->triangle_count();
                if (triangles >= kRateFromTriangles)
                    session.raster_ms_per_triangle = session.raster_mesh_ms / double(triangles);
            };
            // The inside/outside slice before a rasterized mesh (depth-tested with it, seen
            // through it when it is translucent), after a ray-cast picture (which covers the view).
            if (!plan.mesh_ray_cast) session.slice.draw_3d(renderer);
            if (mesh_style.opacity < 1.0f) {
                // X-ray: the structure first (all of it), the nearest surface blended
                // over it, then the structure again where it is in front of the surface.
                draw_overlay();
                if (mesh_style.opacity > 0.0f) draw_surface();
            } else {
                draw_surface();
            }
            if (plan.mesh_ray_cast) session.slice.draw_3d(renderer);
            draw_overlay();
        }
        out.scene_drawn = true;
        cache.finish_frame(key, share, boxes_total, renderer);
        if (split && session.gpu_cast_shown && session.gpu_cast.texture())
            renderer.draw_image(*session.gpu_cast.texture(), layout.ray_view);
        else if (split && session.ray_cast.texture())
            renderer.draw_image(*session.ray_cast.texture(), layout.ray_view);
        // The left half from the core CPU rasterizer instead of OpenGL's own picture.
        if (split && session.ray_cast.left_texture())
            renderer.draw_image(*session.ray_cast.left_texture(), layout.gl_view);
    } else {
        session.view_cache.forget();  // no view (no scene yet, a minimised window)
    }
    return out;
}

/// A screenshot asked for (the View panel's button): this frame, as drawn.
void take_screenshot(Renderer& renderer, Session& session, const FrameInput& input) {
    if (!session.screenshot_path.empty()) {
        const std::string path = std::exchange(session.screenshot_path, {});
        if (auto err = write_png(renderer.read_colour({0, 0, input.width, input.height}), path))
            session.notify(err->message, true);
        else
            session.notify("Screenshot saved: " + path, false);
    }
}

}  // namespace

// [SECTION] The frame

FrameLayout draw_frame(AppState& state, Renderer& renderer, Session& session, const FrameInput& input) {
    // 1. Work finished on the loader thread, and files dropped on the window.
    session.view_cache.start_frame(input.frame_ms);
    session.moving_boxes.start_frame(input.frame_ms, session.overlay);
    session.take_finished_load(state);
    for (const std::string& path : input.dropped_paths) {
        if (looks_like_structure_file(path)) session.use_structure_file(state, path);  // a tree (a student's)
        else session.open_scene(state, path);
    }

    // GPU copies and the structure overlay now, so the panels and the legend of
    // this very frame describe what it draws (and a headless frame is complete).
    session.upload_to_gpu(state.overlay);

    // 2. Fonts and colours (a changed UI scale rebuilds the font atlas), then ImGui's frame.
    ViewSettings look = state.view;
    if (session.lecture.on && input.draw_ui) look.ui_scale = std::max(look.ui_scale, kLectureUiScale);
    session.style.apply(look, renderer);
    widget_audit::begin_frame();
    ImGui::NewFrame();

    // 3. Layout, input, work started; 4. the panels; 5. GL: the picture, panels on top; 6. a screenshot.
    const FramePlan plan = plan_frame(state, session, input);
    // The scaling chart's worker may be waiting for an OpenGL frame: drawn here, before
    // this frame's own drawing begins (which clears it away).
    session.scaling.update(state, session.scene, renderer, plan.layout.gl_view.width, plan.layout.gl_view.height,
                           (plan.ui || plan.lecture) && plan.right_panel == RightPanel::Scaling, input.deterministic);
    if (plan.ui) draw_panels(state, session, input, plan);
    if (plan.lecture) draw_lecture_labels(state, session, input, plan);
    if (state.stepper.open && session.scene && state.camera && !plan.layout.gl_view.empty() &&
        !(plan.lecture && session.lecture.blank))
        session.stepper.draw_labels(make_view3d(*state.camera, plan.layout.gl_view, session.scene->bounds));
    if (state.nearest.open && session.scene && state.camera && !plan.layout.gl_view.empty() &&
        !(plan.lecture && session.lecture.blank))
        session.nearest.draw_labels(make_view3d(*state.camera, plan.layout.gl_view, session.scene->bounds));
    ImGui::Render();
    const FrameLayout out = draw_scene(state, renderer, session, input, plan);
    if (plan.ui || plan.lecture) renderer.draw_imgui(ImGui::GetDrawData());
    take_screenshot(renderer, session, input);
    return out;
}

}  // namespace accelviz
