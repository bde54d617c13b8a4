#include "app/gui/headless.h"

#include <algorithm>
#include <chrono>

#include <imgui.h>

#include "app/gl/renderer.h"
#include "app/gui/session.h"
#include "app/platform/osmesa_context.h"

namespace accelviz {

// [SECTION] HeadlessApp

Expected<std::unique_ptr<HeadlessApp>> HeadlessApp::create(int width, int height) {
    if (width < 16 || height < 16 || width > 8192 || height > 8192)
        return Error{"image size must be between 16 and 8192 pixels"};
    std::unique_ptr<HeadlessApp> app(new HeadlessApp());
    app->width_ = width;
    app->height_ = height;
    app->saved_gl_ = gl;
    app->saved_imgui_ = ImGui::GetCurrentContext();
    app->imgui_ = ImGui::CreateContext();
    ImGui::SetCurrentContext(app->imgui_);
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // PLATFORM.md: headless sets these by hand
    io.DisplaySize = ImVec2(float(width), float(height));
    io.DeltaTime = 1.0f / 60.0f;

    auto context = OsMesaContext::create(width, height);
    if (!context) return Error{context.error()};
    app->context_ = std::move(*context);
    auto renderer = Renderer::create();
    if (!renderer) return Error{renderer.error()};
    app->renderer_ = std::move(*renderer);
    app->session_ = std::make_unique<Session>();
    app->session_->presets.set_dir("");  // a frame's pixels do not depend on the files in assets/presets
    return app;
}

HeadlessApp::~HeadlessApp() {
    // GL objects (session, renderer) before their context; then the caller's state back.
    session_.reset();
    renderer_.reset();
    context_.reset();
    if (imgui_) ImGui::DestroyContext(imgui_);
    ImGui::SetCurrentContext(saved_imgui_);
    gl = saved_gl_;
}

FrameLayout HeadlessApp::draw(AppState& state, FrameInput input) {
    input.width = width_;
    input.height = height_;
    input.deterministic = true;
    ImGui::GetIO().DisplaySize = ImVec2(float(width_), float(height_));
    FrameLayout layout = draw_frame(state, *renderer_, *session_, input);
    gl.Finish();  // llvmpipe renders here: the frame is done when this returns
    return layout;
}

Image HeadlessApp::read_colour() { return renderer_->read_colour({0, 0, width_, height_}); }

std::string HeadlessApp::gl_description() const { return context_->description(); }

// [SECTION] One-shot renders

Expected<HeadlessRender> render_headless(const AppState& state, WindowView view, int width, int height,
                                         int frames, const std::function<void(Session&)>& prepare) {
    if (view == WindowView::Step && !state.stepper.ray) return Error{"view step: no ray to step (pick a pixel)"};

    LoadResult loaded = load_and_build_or_refit(state.scene, state.accel, state.refit_bvh);
    if (!loaded) return Error{loaded.error()};
    return render_headless(state, std::move(*loaded), view, width, height, frames, prepare);
}

Expected<HeadlessRender> render_headless(const AppState& state, std::shared_ptr<const LoadedScene> scene,
                                         WindowView view, int width, int height, int frames,
                                         const std::function<void(Session&)>& prepare) {
    if (!scene) return Error{"no scene to render"};
    auto app = HeadlessApp::create(width, height);
    if (!app) return Error{app.error()};
    if (prepare) prepare((*app)->session());

    HeadlessRender out;
    out.gl_description = (*app)->gl_description();
    AppState frame_state = state;
    (*app)->session().set_scene(frame_state, std::move(scene), state.camera.has_value());
    FrameInput input;
    input.draw_ui = view != WindowView::Structure;
    if (view == WindowView::BuildStep) {
        // The whole window with the construction stepper at build_step.step: check
        // the step against the recorded build (or the file's nodes) first (the
        // stepper would clamp it).
        Session& session = (*app)->session();
        const bool file_tree = session.scene && session.scene->structure_file;
        if (!file_tree && state.accel.type != AccelType::Bvh && state.accel.type != AccelType::Kd)
            return Error{"the build-step view needs a BVH or a KD tree (--accel bvh|kd)"};
        const bool node_order = file_tree || state.accel.type == AccelType::Kd;  // node by node
        frame_state.build_step.active = true;
        frame_state.stepper.open = frame_state.comparison.open = frame_state.two_bvhs.open = false;  // one right panel
        session.build_stepper.update(frame_state, session.scene, true);
        const int step = state.build_step.step;
        if (node_order) {
            const FileOrderTrace* file = session.build_stepper.file_trace();
            if (!file) return Error{"a grid from a file has no nodes to step (the build-step view steps a BVH or KD tree)"};
            const size_t nodes = file->order.size();
            const std::string whose = file_tree ? "the file's tree" : "the KD tree";
            if (nodes == 0) return Error{whose + " has no nodes to step"};
            if (step < 0 || size_t(step) >= nodes)
                return Error{"--step " + std::to_string(step) + " is out of range: " + whose + " has " +
                             std::to_string(nodes) + " nodes (0.." + std::to_string(nodes - 1) + ")"};
        } else {
            const BuildTrace* trace = session.build_stepper.trace();
            if (!trace) return Error{"the build-step view needs a BVH (--accel bvh)"};
            if (trace->steps.empty()) return Error{"the scene has no triangles: the BVH build made no decisions to step"};
            if (step < 0 || size_t(step) >= trace->steps.size())
                return Error{"--step " + std::to_string(step) + " is out of range: the build made " +
                             std::to_string(trace->steps.size()) + " decisions (0.." +
                             std::to_string(trace->steps.size() - 1) + ")"};
        }
    }
    if (view == WindowView::Step) {
        frame_state.stepper.open = true;
        frame_state.build_step.active = false;  // one right panel at a time
        frame_state.comparison.open = frame_state.two_bvhs.open = false;
    }
    if (view == WindowView::FillOrder) {
        frame_state.view.mode = ViewMode::Split;
        frame_state.view.fill_order = true;
    }
    if (view == WindowView::Comparison) {
        frame_state.comparison.open = true;
        frame_state.stepper.open = frame_state.build_step.active = frame_state.two_bvhs.open = false;
    }
    if (view == WindowView::TwoBvhs) {
        frame_state.two_bvhs.open = true;
        frame_state.stepper.open = frame_state.build_step.active = frame_state.comparison.open = false;
    }
    // gui: auto-sized windows appear on the second frame; step: the event list
    // scrolls to the current event on the frame after it is laid out.
    const int count = std::max(frames, view == WindowView::Step ? 3 : input.draw_ui ? 2 : 1);
    FrameLayout layout;
    for (int i = 0; i < count; ++i) {
        const auto start = std::chrono::steady_clock::now();
        layout = (*app)->draw(frame_state, input);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        if (i == 0) out.first_frame_ms = ms;
        if (i == 1 || (i > 1 && ms < out.min_frame_ms)) out.min_frame_ms = ms;
        out.frame_ms = ms;
    }
    out.colour = (*app)->read_colour();
    if (layout.scene_drawn) out.view_depth = (*app)->renderer().read_depth(layout.view_rect);
    out.view = layout.view;
    return out;
}

Expected<Image> render_gui_view_headless(const AppState& state, WindowView view, int width, int height) {
    auto render = render_headless(state, view, width, height);
    if (!render) return Error{render.error()};
    return std::move(render->colour);
}

}  // namespace accelviz
