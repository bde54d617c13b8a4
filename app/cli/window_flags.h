#pragma once
/// The window's flags, on the top-level command: `accelviz [SCENE] [--preset FILE]
/// [structure flags] [camera flags]` opens the window on the state `accelviz render`
/// draws with the same flags: the preset's (or the defaults), with SCENE, the
/// structure flags and the camera flags given laid over it.

#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "app/cli/camera_flags.h"
#include "app/cli/light_flags.h"
#include "app/cli/preset_flag.h"
#include "app/gui/app_state.h"

namespace accelviz::cli {

struct WindowOptions {
    std::string scene;               ///< SCENE as given (empty: the preset's, or the default)
    PresetFlag preset;               ///< --preset, read while parsing (before the structure flags apply)
    AccelConfig accel = AppState{}.accel;  ///< the preset's structure with the flags given over it
    CameraFlags camera;
    bool lecture = false;            ///< --lecture
    std::string draw;                ///< --draw ("": the preset's, else auto)
    LightFlags light;                ///< --shadows, --reflections, --light
    std::string pixel;               ///< --pixel X,Y: open the stepper on that pixel's ray
    int width = 1280, height = 720;  ///< --width, --height: the image --pixel is in
};

/// Opens the traversal stepper on `picked`'s ray, seen from the side, at `step`: what
/// `render --view step` and the window's --pixel show.
void open_stepper_on(AppState& state, const PixelRay& picked, size_t step);

/// Adds --draw raster|raycast|auto (View > Draw with) to a command that draws the
/// window's frame; `auto_here` says how auto chooses in it, `applies_to` (if not
/// empty) which of its views it is for. Sets `draw` as given.
void add_draw_flag(CLI::App& app, std::string& draw, const std::string& auto_here, const std::string& applies_to = "");
/// --draw as given over the state (nothing when not given: the preset's, else auto).
void apply_draw_flag(const std::string& draw, AppState& state);

/// Adds SCENE, --preset, the structure flags and the camera flags to the top-level
/// command (before its subcommands parse theirs).
std::shared_ptr<WindowOptions> add_window_flags(CLI::App& app, const std::string& default_scene);

/// The state to open the window on, or a one-line error naming the flag or the file.
/// Camera flags over no preset camera need the scene's box: the scene is loaded
/// for it (the window then loads it again, from the mesh cache for an OBJ).
Expected<AppState> window_state(const WindowOptions& opt, const std::string& default_scene);

}  // namespace accelviz::cli
