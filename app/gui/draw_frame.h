#pragma once
/// One frame of the window, drawn by the SAME function in the window loop and in
/// headless renders (only the GL context differs), which is what makes the
/// golden images mean something.

#include <string>
#include <vector>

#include "app/gl/renderer.h"
#include "app/gui/app_state.h"
#include "app/gui/session.h"

namespace accelviz {

/// What the frame needs from outside beyond AppState and Session.
struct FrameInput {
    int width = 0, height = 0;           ///< framebuffer size in pixels
    double frame_ms = 0;                 ///< the previous frame's time, for the status line (0: unknown)
    std::vector<std::string> dropped_paths;  ///< files dropped on the window since the last frame
    bool draw_ui = true;                 ///< false: the 3D view alone, over the whole frame ("structure")
    bool deterministic = false;          ///< headless: no times, no animation (golden images)
    /// bench-view: the frame includes the ray-cast mesh of its own camera (Draw with:
    /// ray cast), cast as the window would, and a moving camera is drawn lighter as in
    /// the window (a quarter of the pixels, the overlay's shallow levels); "auto" goes
    /// by measured times. Otherwise headless frames never move and auto estimates.
    bool wait_for_ray_cast = false;
};

/// What the frame laid out, for the caller (read-back, tests).
struct FrameLayout {
    ViewRect view_rect;  ///< where the 3D view was drawn
    View3D view;         ///< its camera and clip planes (valid if a scene is shown)
    bool scene_drawn = false;
};

/// Draws one frame. Before calling: the context is current, and ImGui's platform
/// part has run for this frame (ImGui_ImplGlfw_NewFrame, or io.DisplaySize and
/// io.DeltaTime set by hand). In order: takes a finished load, applies the UI
/// style, runs ImGui (panels, then mouse and keys for the 3D view unless ImGui
/// wants them), and renders the 3D view and the panels.
FrameLayout draw_frame(AppState& state, Renderer& renderer, Session& session, const FrameInput& input);

}  // namespace accelviz
