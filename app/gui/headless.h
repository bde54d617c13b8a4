#pragma once
/// Headless rendering of the window's views through OSMesa, with the same
/// draw_frame() the window uses.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/gl/view3d.h"
#include "app/gui/app_state.h"
#include "app/gui/draw_frame.h"
#include "app/platform/gl_loader.h"
#include "core/render/image.h"
#include "core/util/enum_names.h"
#include "core/util/expected.h"

struct ImGuiContext;

namespace accelviz {

class OsMesaContext;
class Renderer;
struct LoadedScene;
struct Session;

/// The window's views a headless render draws.
enum class WindowView {
    Structure,  ///< the 3D view alone, over the whole image
    Gui,        ///< the whole window frame, panels included
    BuildStep,  ///< the whole frame with the construction stepper at state.build_step.step
                ///< (one of the recorded build's decisions)
    Step,       ///< the whole frame with the traversal stepper open on state.stepper.ray
    Comparison, ///< the whole frame with the comparison panel open (every structure measured)
    FillOrder,  ///< the whole frame, split, with the fill order at state.view.fill
    TwoBvhs,    ///< the whole frame with the two-BVHs panel open (the scene's BVH by two builders)
};
inline constexpr EnumNames<WindowView, 7> kWindowViewNames{{{{WindowView::Structure, "structure"},
                                                              {WindowView::Gui, "gui"},
                                                              {WindowView::BuildStep, "build-step"},
                                                              {WindowView::Step, "step"},
                                                              {WindowView::Comparison, "comparison"},
                                                              {WindowView::FillOrder, "fill-order"},
                                                              {WindowView::TwoBvhs, "two-bvhs"}}}};
constexpr std::string_view to_string(WindowView v) { return kWindowViewNames.name(v); }

/// Renders `view` of `state` at width x height through an OSMesa context
/// (OpenGL 3.3 core; Mesa's llvmpipe). The scene is loaded and built on this
/// thread first. The frame is deterministic (no times or animation), so it can be
/// compared with golden images. Errors: bad scene, no OSMesa, a view the state cannot show.
Expected<Image> render_gui_view_headless(const AppState& state, WindowView view, int width, int height);

/// What render_gui_view_headless does, with more to inspect.
struct HeadlessRender {
    Image colour;
    std::vector<float> view_depth;  ///< depth buffer in [0, 1] of the 3D view's rectangle, top row first
    View3D view;                    ///< the 3D view's camera, rectangle and clip planes
    double frame_ms = 0;            ///< the last frame: draw_frame + glFinish
    double min_frame_ms = 0;        ///< the fastest frame after the first (a loaded machine adds noise)
    double first_frame_ms = 0;      ///< the first (mesh upload, font atlas, lazy shader work)
    std::string gl_description;     ///< GL_VERSION, GL_RENDERER
};

/// `frames` >= 1 frames are drawn, the last read back (more give a steady-state
/// frame time). "gui" draws at least two: ImGui hides a window that sizes
/// itself on its first frame.
/// `prepare` (if set) sees the Session before the first frame (tests give the
/// comparison panel a clock that ticks, so that its figures are the same every run).
Expected<HeadlessRender> render_headless(const AppState& state, WindowView view, int width, int height,
                                         int frames = 1, const std::function<void(Session&)>& prepare = {});
/// The same with the scene already loaded and built (`scene` must be
/// state.scene built with state.accel), e.g. when the caller needed its bounds.
Expected<HeadlessRender> render_headless(const AppState& state, std::shared_ptr<const LoadedScene> scene,
                                         WindowView view, int width, int height, int frames = 1,
                                         const std::function<void(Session&)>& prepare = {});

/// A window without a window: an OSMesa context, a Renderer, its own ImGui
/// context and a Session, drawing with draw_frame() like the window loop does.
/// While it exists its ImGui context and GL table are the current ones; the
/// caller's come back when it is destroyed. Tests drive it frame by frame.
class HeadlessApp {
public:
    static Expected<std::unique_ptr<HeadlessApp>> create(int width, int height);
    ~HeadlessApp();
    HeadlessApp(const HeadlessApp&) = delete;
    HeadlessApp& operator=(const HeadlessApp&) = delete;

    Session& session() { return *session_; }
    Renderer& renderer() { return *renderer_; }
    int width() const { return width_; }
    int height() const { return height_; }

    /// Draws one deterministic frame of `state` (input.width/height are this
    /// app's, input.deterministic is set) and waits for GL to finish it.
    FrameLayout draw(AppState& state, FrameInput input);
    Image read_colour();
    std::string gl_description() const;

private:
    HeadlessApp() = default;
    int width_ = 0, height_ = 0;
    GlFunctions saved_gl_;  ///< the caller's table, restored by the destructor
    ImGuiContext* saved_imgui_ = nullptr;
    ImGuiContext* imgui_ = nullptr;
    std::unique_ptr<OsMesaContext> context_;
    std::unique_ptr<Renderer> renderer_;
    std::unique_ptr<Session> session_;
};

}  // namespace accelviz
