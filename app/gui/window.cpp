#include "app/gui/window.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
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

/// ImGui 1.86 reads the keyboard once a frame: which keys are down (io.KeysDown)
/// and the characters typed since the last frame, characters first (the input
/// queue that keeps events in order came in 1.87). When several key events fall
/// between two frames, which happens all the time when a frame is slow (a big
/// scene on a software renderer) and always for a presentation clicker, their
/// order is lost: a tap (press and release) is never seen, two PageDowns count as
/// one, and "Ctrl+A, Backspace, new text, Return" in a text field comes out garbled.
///
/// This sits in front of the GLFW backend's key and character callbacks. It queues
/// the events and, before each frame, hands ImGui the longest run of them whose
/// order ImGui cannot get wrong; the rest wait for the next frames, which the main
/// loop draws at once. A run ends before
///  - an event of a key that already changed in this frame (a tap spans two frames;
///    while a text field has the keyboard, only for modifiers and the keys below);
///  - the press of a key ImGui edits text or navigates with (io.KeyMap: arrows,
///    Backspace, Return, Ctrl+A ...) once characters or another such press went in;
///  - a character once such a press went in;
///  - a modifier (Shift, Ctrl, Alt, Super) going up or down once a key it may
///    modify was pressed (ImGui reads the modifiers once a frame: Ctrl let go
///    just after A must not turn Ctrl+A into A).
/// Ordinary typing (letter keys and their characters) still goes in many per frame.
class KeyboardTrickle {
public:
    /// Call after ImGui_ImplGlfw_InitForOpenGL installed its callbacks.
    static void install(GLFWwindow* window) {
        key_backend_ = glfwSetKeyCallback(window, &on_key);
        char_backend_ = glfwSetCharCallback(window, &on_char);
    }

    /// Call before each frame: ImGui gets the events this frame can take.
    static void deliver() {
        std::set<int> changed;
        bool characters = false, editing_press = false, shortcut_press = false;
        // In a text field a letter's key state is read by nobody (shortcuts are
        // off): its taps need not span frames, only its characters' order counts.
        // A modifier's do (Ctrl+A: Ctrl may be let go before A).
        const bool typing = ImGui::GetIO().WantTextInput;
        while (!queue_.empty()) {
            const Event& e = queue_.front();
            if (e.is_char) {
                if (editing_press) break;
                characters = true;
                if (char_backend_) char_backend_(e.window, e.codepoint);
            } else {
                const bool press = e.action == GLFW_PRESS;
                if (e.action != GLFW_REPEAT && e.key != GLFW_KEY_UNKNOWN) {
                    const bool editing = is_editing_key(e.key);
                    const bool modifier = e.key >= GLFW_KEY_LEFT_SHIFT && e.key <= GLFW_KEY_RIGHT_SUPER;
                    if (changed.count(e.key) && (editing || modifier || !typing)) break;
                    if (modifier && shortcut_press) break;
                    if (press && editing) {
                        if (characters || editing_press) break;
                        editing_press = true;
                    }
                    if (press && !modifier && (editing || !typing)) shortcut_press = true;
                    changed.insert(e.key);
                }
                if (key_backend_) key_backend_(e.window, e.key, e.scancode, e.action, e.mods);
            }
            queue_.pop_front();
        }
    }

    /// Events still waiting for a frame.
    static bool pending() { return !queue_.empty(); }

private:
    struct Event {
        GLFWwindow* window;
        bool is_char;
        int key, scancode, action, mods;
        unsigned int codepoint;
    };
    static void on_key(GLFWwindow* window, int key, int scancode, int action, int mods) {
        queue_.push_back({window, false, key, scancode, action, mods, 0});
    }
    static void on_char(GLFWwindow* window, unsigned int codepoint) {
        queue_.push_back({window, true, 0, 0, 0, 0, codepoint});
    }
    static bool is_editing_key(int key) {
        for (int mapped : ImGui::GetIO().KeyMap)
            if (mapped == key) return true;
        return false;
    }
    static inline GLFWkeyfun key_backend_ = nullptr;
    static inline GLFWcharfun char_backend_ = nullptr;
    static inline std::deque<Event> queue_;
};

/// ACCELVIZ_UI_SNAPSHOT=FILE: after each frame that changed anything, FILE holds
/// what a scripted test of the real window needs to act and to check: the app
/// state (as a saved state), the status line, the message shown, whether work is
/// under way, the text field being typed into, the mouse, and every widget's label and rectangle. It is written to
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
        j["light_markers"] = session.light_markers;
        j["query_markers"] = session.query_markers;
        // What is on screen, which lags the state while a load or a build runs.
        if (session.scene)
            j["shown"] = {{"scene", session.scene->source},
                          {"structure", session.scene->accel->name()},
                          {"triangles", session.scene->mesh->triangle_count()},
                          {"refitted", session.scene->refitted}};
        if (state.stepper.ray && session.stepper.traced_ray) {
            const SteppedRay& traced = session.stepper.trace;
            j["stepped_ray"] = {{"structure", traced.structure},
                                {"events", traced.events.size()},
                                {"any_hit", traced.query == StopAt::AnyHit},
                                {"hit_triangle", traced.hit.found() ? nlohmann::json(traced.hit.tri) : nlohmann::json()}};
        }
        if (state.nearest.open && session.nearest.search) {
            const SteppedNearest& n = *session.nearest.search;
            j["nearest_search"] = {{"structure", n.structure},
                                   {"events", n.events.size()},
                                   {"point", {n.query.x, n.query.y, n.query.z}},
                                   {"triangle", n.result.found() ? nlohmann::json(n.result.tri) : nlohmann::json()},
                                   {"distance", n.result.found() ? nlohmann::json(n.result.distance()) : nlohmann::json()}};
        }
        if (session.gpu_cast_shown && session.gpu_cast.shown()) {
            const GpuCast& gpu = *session.gpu_cast.shown();
            size_t hits = 0;
            for (uint32_t tri : gpu.tri) hits += tri != Hit::kNoHit ? 1 : 0;
            j["gpu_cast"] = {{"width", gpu.width}, {"height", gpu.height}, {"hits", hits}, {"stale", session.gpu_cast.stale()}};
        } else if (!session.gpu_cast.error().empty()) {
            j["gpu_cast"] = {{"error", session.gpu_cast.error()}};
        }
        if (const InsideSlice* slice = session.slice.shown()) {
            size_t inside = 0;
            for (uint8_t v : slice->votes) inside += v >= 2 ? 1 : 0;
            j["slice"] = {{"axis", slice->spec.axis}, {"position", slice->position}, {"points", slice->votes.size()},
                          {"inside", inside}};
        }
        if (const StructureComparison* c = session.comparison.measured()) {
            nlohmann::json rows = nlohmann::json::array();
            for (const StructureMeasurement& row : c->rows)
                rows.push_back({{"label", row.label}, {"rays", row.rays}, {"mismatches", row.mismatches}});
            j["comparison"] = {{"width", c->width}, {"height", c->height}, {"rows", rows}};
        }
        if (const TwoBvhs* t = session.two_bvhs.measured()) {
            nlohmann::json trees = nlohmann::json::array();
            for (const BvhTreeSummary& tree : t->trees)
                trees.push_back({{"builder", to_string(tree.builder)},
                                 {"sah_cost", tree.stats.sah_cost},
                                 {"nodes_per_ray", tree.nodes_per_ray}});
            j["two_bvhs"] = {{"width", t->width}, {"height", t->height}, {"trees", trees}};
        }
        j["scaling_measuring"] = session.scaling.busy();
        if (const ScalingResult* r = session.scaling.measured()) {
            nlohmann::json points = nlohmann::json::array();
            for (const ScalingPoint& p : r->points) {
                const nlohmann::json gl = p.gl_raster_ms ? nlohmann::json(*p.gl_raster_ms) : nlohmann::json(nullptr);
                points.push_back({{"triangles", p.triangles},
                                  {"gl_raster_ms", gl},
                                  {"cpu_raster_ms", p.cpu_raster_ms},
                                  {"cast_ms", p.cast_ms}});
            }
            j["scaling"] = {{"width", r->width}, {"height", r->height}, {"points", points}};
        }
        j["status"] = session.stats_bar.last_line;
        // Draw with: what drew the mesh, the ray-cast picture's pixel divisor (1: every
        // pixel, 2: a quarter; 0: none shown), and how many quarter pictures were shown.
        const auto& cast = session.surface_cast.shown();
        j["mesh"] = {{"drawn_by", session.mesh_ray_cast ? "raycast" : "raster"},
                     {"cast_divisor", session.mesh_ray_cast && cast ? cast->divisor : 0},
                     {"quarter_pictures", session.surface_cast.quarter_pictures_shown()}};
        j["view_cache_hits"] = session.view_cache.hits();  // frames that drew the 3D view's kept picture
        j["lecture"] = {{"on", session.lecture.on}, {"caption", session.lecture.caption}, {"blank", session.lecture.blank},
                        {"preset", session.presets.current()}, {"font_size", ImGui::GetFontSize()}};
        j["message"] = session.message;
        j["busy"] = session.has_pending_work();
        j["loading"] = session.loader.busy() || session.loader.has_result();  // a scene or structure still coming
        j["pending"] = nlohmann::json::array();  // what keeps it busy, by name (for a test that waits in vain)
        for (const char* name : session.pending_work()) j["pending"].push_back(name);
        j["typing_into"] = widget_audit::active_text_field();
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

int run_window(AppState state, const std::string& preset_path, bool lecture, bool first_preset) {
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
    KeyboardTrickle::install((*window)->handle());

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
            (*renderer)->prepare_frame_copies();
            // 3. The scene loads on the worker; the window is drawn meanwhile.
            Session session;
            session.loader.on_finished = [] { GlfwWindow::wake_up(); };
            session.ray_cast.set_on_finished([] { GlfwWindow::wake_up(); });
            session.surface_cast.set_on_finished([] { GlfwWindow::wake_up(); });
            session.build_stepper.set_on_finished([] { GlfwWindow::wake_up(); });
            session.comparison.set_on_finished([] { GlfwWindow::wake_up(); });
            session.two_bvhs.set_on_finished([] { GlfwWindow::wake_up(); });
            session.scaling.set_on_finished([] { GlfwWindow::wake_up(); });
            session.scaling.on_frame_wanted = [] { GlfwWindow::wake_up(); };
            if (first_preset && !session.presets.entries().empty()) {
                session.presets.load(0, state, session);
            } else {
                session.open_scene(state, state.scene, /*keep_camera=*/state.camera.has_value());
                if (!preset_path.empty()) session.presets.opened_with(preset_path, session);
            }
            session.lecture.on = lecture;

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
                // A still view drawn a share per frame goes on at once, as while a key is held.
                const bool input_held =
                    any_input_held() || KeyboardTrickle::pending() || session.view_cache.drawing_on();
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
                KeyboardTrickle::deliver();
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
                if (session.lecture.on != (*window)->fullscreen()) (*window)->set_fullscreen(session.lecture.on);
                if (check_ids) report_duplicate_ids(reported_duplicates);
                if (snapshot) snapshot->write(state, session, layout);
                frame_ms = std::chrono::duration<double, std::milli>(clock::now() - start).count();
            }
            // Closed while work runs: the loader's load or build stops at its next check,
            // but the steppers' recordings and the split view's ray cast have no point
            // where they could stop, and waiting for them (the workers are joined below)
            // would keep a closed window's process alive. Nothing is left to save, so the
            // process ends here.
            if (session.loader.busy() || session.build_stepper.busy() || session.ray_cast.busy() ||
                session.surface_cast.busy() ||
                session.stepper.has_pending_work() || session.comparison.busy() ||
                session.two_bvhs.busy() || session.slice.busy() || session.scaling.busy()) {
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
