#include "app/gui/window.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>

#include "app/gl/renderer.h"
#include "app/gui/draw_frame.h"
#include "app/gui/session.h"
#include "app/gui/widget_audit.h"
#include "app/platform/glfw_window.h"

namespace accelviz {

namespace {

/// A key or mouse button held down (the view moves while arrows are held).
bool any_input_held() {
    const ImGuiIO& io = ImGui::GetIO();
    for (bool down : io.MouseDown)
        if (down) return true;
    for (bool down : io.KeysDown)
        if (down) return true;
    return false;
}

/// ImGui 1.86 sees a key only as "down at the start of a frame" (io.KeysDown; the
/// input queue came in 1.87), so a key pressed and released between two frames
/// was never seen: a quick tap of S, or a presentation clicker's PageDown, which
/// sends both at once. This sits in front of the GLFW backend's key callback and
/// holds such a release back until a frame has been drawn with the key down.
class KeyTapKeeper {
public:
    /// Call after ImGui_ImplGlfw_InitForOpenGL installed its callbacks.
    static void install(GLFWwindow* window) { backend_ = glfwSetKeyCallback(window, &on_key); }

    /// Call after each drawn frame: the held releases go to ImGui now.
    static void frame_drawn() {
        pressed_since_frame_.clear();
        for (const Release& r : std::exchange(held_, {}))
            if (backend_) backend_(r.window, r.key, r.scancode, GLFW_RELEASE, r.mods);
    }

private:
    struct Release {
        GLFWwindow* window;
        int key, scancode, mods;
    };
    static void on_key(GLFWwindow* window, int key, int scancode, int action, int mods) {
        if (action == GLFW_PRESS) pressed_since_frame_.insert(key);
        if (action == GLFW_RELEASE && pressed_since_frame_.count(key)) {
            held_.push_back({window, key, scancode, mods});
            return;
        }
        if (backend_) backend_(window, key, scancode, action, mods);
    }
    static inline GLFWkeyfun backend_ = nullptr;
    static inline std::set<int> pressed_since_frame_;
    static inline std::vector<Release> held_;
};

/// ACCELVIZ_UI_SNAPSHOT=FILE: after each frame that changed anything, FILE holds
/// what a scripted test of the real window needs to act and to check: the app
/// state (as a saved state), the status line, the message shown, whether work is
/// under way, the mouse, and every widget's label and rectangle. It is written to
/// FILE.tmp and renamed, so a reader never sees half a file.
class UiSnapshotWriter {
public:
    explicit UiSnapshotWriter(std::string path) : path_(std::move(path)) {}

    void write(const AppState& state, const Session& session, const FrameLayout& layout) {
        const ImGuiIO& io = ImGui::GetIO();
        nlohmann::json j;
        j["state"] = to_json(state);
        j["size"] = {io.DisplaySize.x, io.DisplaySize.y};
        j["view"] = {layout.view_rect.x, layout.view_rect.y, layout.view_rect.width, layout.view_rect.height};
        // What is on screen, which lags the state while a load or a build runs.
        if (session.scene)
            j["shown"] = {{"scene", session.scene->source},
                          {"structure", session.scene->accel->name()},
                          {"triangles", session.scene->mesh->triangle_count()}};
        if (state.stepper.ray && session.stepper.traced_ray) {
            const SteppedRay& traced = session.stepper.trace;
            j["stepped_ray"] = {{"structure", traced.structure},
                                {"events", traced.events.size()},
                                {"hit_triangle", traced.hit.found() ? nlohmann::json(traced.hit.tri) : nlohmann::json()}};
        }
        j["status"] = session.stats_bar.last_line;
        j["message"] = session.message;
        j["busy"] = session.has_pending_work();
        j["mouse"] = {{"x", io.MousePos.x}, {"y", io.MousePos.y},
                      {"down", {io.MouseDown[0], io.MouseDown[1], io.MouseDown[2]}}};
        nlohmann::json widgets = nlohmann::json::array();
        for (const widget_audit::Widget& w : widget_audit::widgets())
            widgets.push_back({{"label", w.label},
                               {"text", widget_audit::visible_text(w.label)},
                               {"window", w.window},
                               {"hidden", w.hidden},
                               {"rect", {w.x0, w.y0, w.x1, w.y1}}});
        j["widgets"] = std::move(widgets);
        nlohmann::json duplicates = nlohmann::json::array();
        for (const widget_audit::Duplicate& d : widget_audit::duplicates())
            duplicates.push_back({{"label", d.label}, {"window", d.window}});
        j["duplicate_ids"] = std::move(duplicates);
        std::string text = j.dump();
        if (text == last_) return;
        last_ = std::move(text);
        // The frame's number, outside the comparison: a reader can wait for a later
        // frame (ImGui places a new popup one frame after it first lays it out).
        j["frame"] = ImGui::GetFrameCount();
        text = j.dump();
        const std::string temporary = path_ + ".tmp";
        {
            std::ofstream out(temporary, std::ios::trunc);
            out << text << "\n";
            if (!out) return;  // a test harness problem, not the user's: the window goes on
        }
        std::rename(temporary.c_str(), path_.c_str());
    }

private:
    std::string path_;
    std::string last_;
};

/// Debug builds: a widget ID used twice in a frame is said on stderr (once per label).
void report_duplicate_ids(std::set<std::string>& reported) {
    for (const widget_audit::Duplicate& d : widget_audit::duplicates())
        if (reported.insert(d.window + "/" + d.label).second)
            std::cerr << "accelviz: two widgets share an ImGui ID in " << d.window << ": \"" << d.label
                      << "\" (the second cannot be clicked)\n";
}

}  // namespace

int run_window(AppState state) {
    // 1. The window and its GL context.
    auto window = GlfwWindow::create("accelviz", 1600, 900);
    if (!window) {
        std::cerr << "accelviz: " << window.error() << "\n"
                  << "accelviz: no window without a display; render images instead, e.g.\n"
                  << "    accelviz render " << state.scene << " --out image.png\n";
        return 1;
    }

    // 2. Dear ImGui: its GLFW backend (inside Debian's libimgui.a) feeds it
    //    mouse and keys; our Renderer draws it.
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // the layout is fixed; nothing to save
    ImGui_ImplGlfw_InitForOpenGL((*window)->handle(), /*install_callbacks=*/true);
    KeyTapKeeper::install((*window)->handle());

    std::optional<UiSnapshotWriter> snapshot;
    if (const char* path = std::getenv("ACCELVIZ_UI_SNAPSHOT"); path && *path) snapshot.emplace(path);
#ifndef NDEBUG
    const bool check_ids = true;
#else
    const bool check_ids = false;
#endif
    widget_audit::set_enabled(snapshot.has_value() || check_ids);
    std::set<std::string> reported_duplicates;

    int exit_code = 0;
    {
        auto renderer = Renderer::create();
        if (!renderer) {
            std::cerr << "accelviz: " << renderer.error() << "\n";
            exit_code = 1;
        } else {
            // 3. The scene loads on the worker; the window is drawn meanwhile.
            Session session;
            session.loader.on_finished = [] { GlfwWindow::wake_up(); };
            session.ray_cast.set_on_finished([] { GlfwWindow::wake_up(); });
            session.build_stepper.set_on_finished([] { GlfwWindow::wake_up(); });
            session.open_scene(state, state.scene, /*keep_camera=*/state.camera.has_value());

            // 4. The loop. It sleeps until something happens: an input or window
            //    event, a load finishing (the loader wakes it), or a held key or
            //    button. It draws a few frames after each event (ImGui's hover
            //    and release states), keeps drawing while the user holds a key,
            //    and while a load or build runs draws ten frames a second (the
            //    indicator counts seconds): a frame of a big scene takes both
            //    cores for tens of ms on a software renderer, time the work needs.
            using clock = std::chrono::steady_clock;
            double frame_ms = 0;
            int frames_to_draw = 3;
            uint64_t events_seen = 0;
            bool was_working = false;
            while (!(*window)->should_close()) {
                const bool input_held = any_input_held();
                const bool working = session.has_pending_work();
                (*window)->process_events(frames_to_draw > 0 || input_held ? 0.0 : working ? 0.1 : 0.5);
                // Events, and work finishing, are followed by a few frames: ImGui
                // shows a new auto-sized window one frame late, hover states settle.
                if ((*window)->event_count() != events_seen || input_held || (was_working && !working))
                    frames_to_draw = 3;
                else if (working)
                    frames_to_draw = std::max(frames_to_draw, 1);
                was_working = working;
                events_seen = (*window)->event_count();
                if (frames_to_draw == 0) continue;
                --frames_to_draw;

                const auto start = clock::now();
                ImGui_ImplGlfw_NewFrame();
                FrameInput input;
                input.width = (*window)->framebuffer_width();
                input.height = (*window)->framebuffer_height();
                input.frame_ms = frame_ms;
                input.dropped_paths = (*window)->take_dropped_paths();
                if (input.width <= 0 || input.height <= 0) {  // minimised: nothing to draw
                    ImGui::GetIO().DisplaySize = ImVec2(1, 1);
                    input.width = input.height = 1;
                }
                const FrameLayout layout = draw_frame(state, **renderer, session, input);
                (*window)->swap_buffers();
                KeyTapKeeper::frame_drawn();
                if (check_ids) report_duplicate_ids(reported_duplicates);
                if (snapshot) snapshot->write(state, session, layout);
                frame_ms = std::chrono::duration<double, std::milli>(clock::now() - start).count();
            }
            // Closed while a load or a build runs: that work has no point where it could
            // stop, and waiting for it (the workers are joined below) would keep a closed
            // window's process alive for as long as a 10M-triangle build takes. Nothing is
            // left to save, so the process ends here.
            if (session.loader.busy() || session.build_stepper.busy() || session.ray_cast.busy() ||
                session.stepper.has_pending_work()) {
                std::cout.flush();
                std::cerr.flush();
                std::_Exit(exit_code);
            }
        }
    }  // Session and Renderer go before the context does.

    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    return exit_code;
}

}  // namespace accelviz
