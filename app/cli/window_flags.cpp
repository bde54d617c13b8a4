#include "app/cli/window_flags.h"

#include "app/cli/accel_flags.h"
#include "app/cli/flag_checks.h"
#include "app/cli/progress.h"
#include "app/gui/stepper_panel.h"
#include "core/geometry/scene.h"

namespace accelviz::cli {

void add_draw_flag(CLI::App& app, std::string& draw, const std::string& auto_here, const std::string& applies_to) {
    app.add_option("--draw", draw,
                   applies_to + "How the 3D view draws the mesh: raster (OpenGL, every triangle) | raycast (the CPU ray caster "
                   "through the structure, its depth under the overlay; a quarter of the pixels while the camera "
                   "moves) | auto (" + auto_here + "). Default: the preset's, else auto")
        ->check(CLI::IsMember(kDrawWithNames.names()));
}

void apply_draw_flag(const std::string& draw, AppState& state) {
    if (!draw.empty()) state.view.draw_with = *kDrawWithNames.parse(draw);  // CLI11 checked the name
}

std::shared_ptr<WindowOptions> add_window_flags(CLI::App& app, const std::string& default_scene) {
    auto opt = std::make_shared<WindowOptions>();
    app.add_option("SCENE", opt->scene,
                   "Scene for the window: an OBJ path or builtin:NAME (default: " + default_scene +
                       "; with --preset, replaces the preset's scene)");
    add_preset_flag(app, opt->preset, opt->accel,
                    "Open the window on this saved state (a JSON file, or a shipped preset's name, e.g. "
                    "30-grid-stadium), as `accelviz render --preset` draws it; SCENE, the structure flags and the "
                    "camera flags given replace its values");
    add_accel_flags(app, opt->accel);
    opt->accel.type = AppState{}.accel.type;  // the window's default structure (add_accel_flags sets the commands')
    opt->camera.add_to(app);
    app.add_flag("--lecture", opt->lecture,
                 "Open in lecture mode: full screen, no sidebar (a stepper's panel stays), text at projector "
                 "scale, the preset's number, title and caption in a caption bar (C hides it); PageDown / PageUp "
                 "go through the presets (Home / End too, unless a stepper is open), B blanks the screen, L "
                 "leaves. Without SCENE or --preset, starts at the first preset");
    add_draw_flag(app, opt->draw, "whichever the window measures faster on the scene, the View panel's "
                                  "\"Draw with\"");
    add_light_flags(app, opt->light);
    app.add_option("--pixel", opt->pixel,
                   "Open the traversal stepper on the ray of pixel X,Y (0,0 = top left) of a --width x --height "
                   "image under the camera flags: the ray `accelviz trace --pixel X,Y` prints");
    app.add_option("--width", opt->width, "With --pixel: the image's width")
        ->check(whole_number(1, 16384))
        ->capture_default_str();
    app.add_option("--height", opt->height, "With --pixel: the image's height")
        ->check(whole_number(1, 16384))
        ->capture_default_str();
    return opt;
}

void open_stepper_on(AppState& state, const PixelRay& picked, size_t step) {
    state.camera = stepper_side_view(picked.camera, picked.ray);
    state.overlay.mesh_opacity = 0.5f;  // as the window does when the stepper opens: the boxes lie inside the mesh
    state.stepper.open = true;
    state.stepper.ray = picked.ray;
    state.stepper.any_hit = false;
    state.stepper.pixel = std::array<int, 2>{picked.x, picked.y};
    state.stepper.step = step;
}

Expected<AppState> window_state(const WindowOptions& opt, const std::string& default_scene) {
    if (!opt.preset.error.empty()) return Error{"--preset: " + opt.preset.error};
    if (auto err = validate(opt.accel)) {
        if (opt.preset.state && validate(opt.preset.state->accel)) return Error{"--preset: " + opt.preset.path + ": structure: " + err->message};
        return *err;
    }
    AppState state = opt.preset.state.value_or(AppState{});
    if (!opt.scene.empty()) state.scene = opt.scene;
    else if (!opt.preset.state) state.scene = default_scene;
    state.accel = opt.accel;
    apply_draw_flag(opt.draw, state);
    auto light = apply_light_flags(opt.light, state.light);
    if (!light) return Error{light.error()};
    state.light = *light;
    auto mirrored = apply_mirror_flag(opt.light, state.scene);
    if (!mirrored) return Error{mirrored.error()};
    state.scene = *mirrored;
    if (!opt.pixel.empty()) {
        auto picked = [&] {
            const StepProgress progress("window", "loading " + state.scene + " for --pixel");
            return pixel_ray(state.scene, opt.pixel, opt.width, opt.height, opt.camera);
        }();
        if (!picked) return Error{picked.error()};
        open_stepper_on(state, *picked, 0);
        return state;
    }
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
