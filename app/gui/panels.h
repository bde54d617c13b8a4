#pragma once
/// The panels: each a struct that owns its UI state and draws itself into the
/// sidebar with draw(). They change AppState (what to show) and ask Session for
/// work (loading); they never load or build on the UI thread themselves.

#include <memory>
#include <string>

#include "app/gui/app_state.h"
#include "app/gui/structure_overlay.h"

namespace accelviz {

struct Session;

/// Pick a built-in scene, open an OBJ by path (or drop a file on the window).
struct ScenePanel {
    std::string source_text;   ///< the text field; follows AppState::scene until edited
    std::string shown_source;  ///< AppState::scene when source_text was last synced
    // A moving scene's timeline (builtin:moving, builtin:wave).
    float time = 0;            ///< the slider's t (follows the scene's while idle)
    bool playing = false;      ///< t advances by kPlaySpeed per second, a frame at a time
    static constexpr float kPlaySpeed = 0.1f;  ///< units of t (one period) per second
    /// `dt`: seconds since the last frame (0 in golden images: play does not advance).
    void draw(AppState& state, Session& session, double dt);

private:
    void draw_timeline(AppState& state, Session& session, double dt);
};

/// The structure and its build parameters (a change rebuilds it on the worker),
/// and what of it the 3D view shows.
struct StructurePanel {
    std::string file_text;  ///< the "From file" field
    void draw(AppState& state, Session& session);

private:
    void draw_overlay_settings(AppState& state, const Session& session);
};

/// The current structure's build statistics and what the overlay's colours mean.
struct StatsPanel {
    bool open_at_start = false;  ///< the section starts open (headless frames that show it)
    /// The leaf-size / cell-occupancy histogram of `histogram_of` (remade when the structure changes).
    std::weak_ptr<const Accelerator> histogram_of;
    LeafHistogram histogram;
    /// A structure from a file: its shape (remade when another file is loaded).
    std::weak_ptr<const CheckedStructureFile> figures_of;
    StructureFigures figures;
    void draw(const AppState& state, const Session& session);
};

/// Camera and the lecture-hall settings: UI scale, theme, background.
struct ViewPanel {
    float ui_scale_edit = 0;   ///< the slider's value; applied when released (font rebuild)
    bool fill_playing = false;  ///< the fill order animates (not state: no animation in a saved frame)
    float fill_speed = 0.1f;    ///< share of the work per second while playing
    bool editing_scale = false;
    bool copied = false;       ///< "copied" feedback after the copy button
    std::string state_path = "accelviz-state.json";      ///< save / load the whole state
    std::string screenshot_path = "accelviz-screenshot.png";
    void draw(AppState& state, Session& session, double view_aspect);
    /// Playing: moves the fill order on by `seconds` x speed (stops at the end, and when
    /// the fill order or the split view is off).
    void advance_fill(ViewSettings& view, double seconds, bool split);
    /// Play (from the start when at the end) or pause the fill order (its button, Space).
    void play_or_pause_fill(ViewSettings& view);

private:
    void draw_scale(ViewSettings& view);                  ///< UI scale, presets for desk and projector, line width
    static void draw_colours(ViewSettings& view);         ///< theme and background
    void draw_split_choices(ViewSettings& view);          ///< raster | ray cast and what each half shows
    void draw_fill_order(ViewSettings& view);             ///< the fill order: share done, play, speed, step
    static void draw_light(AppState& state, const Session& session);  ///< the point light, shadows, reflections
    static void draw_slice(AppState& state, const Session& session);  ///< the inside/outside slice
    void draw_camera(AppState& state, const Session& session, double view_aspect);
    void draw_files(AppState& state, Session& session);   ///< state JSON save / load, screenshots
};

/// One line at the bottom: scene, triangles, structure, build and frame times.
struct StatsBar {
    /// `frame_ms` <= 0 or `deterministic`: times are left out (golden images).
    void draw(const AppState& state, const Session& session, double frame_ms, bool deterministic);
    std::string last_line;  ///< the text drawn last (scripted window tests read it)
};

/// The keyboard and mouse shortcuts (F1).
struct HelpWindow {
    void draw(AppState& state);
};

}  // namespace accelviz
