#include "app/cli/window_flags.h"

#include "app/cli/accel_flags.h"
#include "app/cli/progress.h"
#include "app/gui/presets.h"
#include "core/geometry/scene.h"

namespace accelviz::cli {

std::shared_ptr<WindowOptions> add_window_flags(CLI::App& app, const std::string& default_scene) {
    auto opt = std::make_shared<WindowOptions>();
    app.add_option("SCENE", opt->scene,
                   "Scene for the window: an OBJ path or builtin:NAME (default: " + default_scene +
                       "; with --preset, replaces the preset's scene)");
    // Before the structure flags: CLI11 applies options in the order they were added,
    // so the flags given apply on top of the preset's structure (as in render).
    app.add_option_function<std::string>(
        "--preset",
        [opt](const std::string& name_or_path) {
            const std::string path = resolve_preset(name_or_path);
            opt->preset_path = path;
            auto state = load_app_state_file(path);
            if (!state) {
                opt->preset_error = state.error();
                return;
            }
            opt->accel = state->accel;
            opt->preset = std::move(*state);
        },
        "Open the window on this saved state (a JSON file, or a shipped preset's name, e.g. 08-grid-stadium), "
        "as `accelviz render --preset` draws it; SCENE, the structure flags and the camera flags given replace "
        "its values");
    add_accel_flags(app, opt->accel);
    opt->accel.type = AppState{}.accel.type;  // the window's default structure (add_accel_flags sets the commands')
    opt->camera.add_to(app);
    return opt;
}

Expected<AppState> window_state(const WindowOptions& opt, const std::string& default_scene) {
    if (!opt.preset_error.empty()) return Error{"--preset: " + opt.preset_error};
    if (auto err = validate(opt.accel)) {
        if (opt.preset && validate(opt.preset->accel)) return Error{"--preset: " + opt.preset_path + ": structure: " + err->message};
        return *err;
    }
    AppState state = opt.preset.value_or(AppState{});
    if (!opt.scene.empty()) state.scene = opt.scene;
    else if (!opt.preset) state.scene = default_scene;
    state.accel = opt.accel;
    if (opt.camera.any()) {
        if (state.camera) {
            auto params = opt.camera.resolve(*state.camera);
            if (!params) return Error{params.error()};
            state.camera = *params;
        } else {
            auto mesh = [&] {
                const StepProgress progress("window", "loading " + state.scene + " for the camera flags");
                return load_scene(state.scene);
            }();
            if (!mesh) return Error{mesh.error()};
            auto params = opt.camera.resolve(mesh->bounds());
            if (!params) return Error{params.error()};
            state.camera = *params;
        }
    }
    return state;
}

}  // namespace accelviz::cli
