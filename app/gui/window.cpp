#include "app/gui/window.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <iostream>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>

#include "app/gl/renderer.h"
#include "app/gui/draw_frame.h"
#include "app/gui/session.h"
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
            //    and release states) and keeps drawing while a load runs (the
            //    indicator counts seconds) or the user holds a key.
            using clock = std::chrono::steady_clock;
            double frame_ms = 0;
            int frames_to_draw = 3;
            uint64_t events_seen = 0;
            while (!(*window)->should_close()) {
                const bool busy = session.has_pending_work() || any_input_held();
                (*window)->process_events(frames_to_draw > 0 || busy ? 0.0 : 0.5);
                // Events, and work finishing, are followed by a few frames: ImGui
                // shows a new auto-sized window one frame late, hover states settle.
                if ((*window)->event_count() != events_seen || busy) frames_to_draw = 3;
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
                draw_frame(state, **renderer, session, input);
                (*window)->swap_buffers();
                frame_ms = std::chrono::duration<double, std::milli>(clock::now() - start).count();
            }
        }
    }  // Session and Renderer go before the context does.

    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    return exit_code;
}

}  // namespace accelviz
