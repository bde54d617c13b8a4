#include "app/gui/session.h"

#include "core/geometry/scene.h"

namespace accelviz {

void Session::open_scene(const AppState& state, const std::string& source, bool keep_camera) {
    keep_camera_on_load = keep_camera;
    // A moving scene at a later time, refitting: the BVH of its t = 0, refitted to it.
    if (auto start = refit_start(source, state.accel, state.refit_bvh))
        return loader.request_refit_from(*start, source, state.accel);
    loader.request(source, state.accel);
}

void Session::open_scene_at_time(const AppState& state, double t, bool refit) {
    if (!scene) return;
    auto source = scene_at_time(scene->source, t);
    if (!source) return notify(source.error(), true);
    keep_camera_on_load = true;
    // Refitting continues the chain of refitted trees; a scene built at a later time
    // (refit just ticked) starts it again from the t = 0 build.
    const std::optional<double> shown_t = scene_time(scene->source);
    if (refit && !scene->refitted && shown_t && *shown_t != 0.0) {
        if (auto start = refit_start(*source, state.accel, true))
            return loader.request_refit_from(*start, *source, state.accel);
    }
    if (refit) loader.request_refit(*source, scene);
    else loader.request(*source, state.accel);
}

void Session::use_structure_file(AppState& state, const std::string& path) {
    state.accel.structure_file = path;
    rebuild_structure(state);
}

void Session::rebuild_structure(const AppState& state) {
    if (!scene) return;
    keep_camera_on_load = true;
    loader.request_rebuild(scene, state.accel);
}

void Session::take_finished_load(AppState& state) {
    std::optional<LoadResult> result = loader.take_result();
    if (!result) return;
    if (!loader.busy()) presets.scene_arrived();  // (a newer request is still coming otherwise)
    if (!*result) {
        // A failed load is shown and the previous scene kept (docs/architecture.md, "Errors");
        // a cancelled one is a notice.
        message_is_error = !was_cancelled(*result);
        message = message_is_error ? result->error() : "Cancelled";
        if (scene) {
            message += "  (keeping " + scene->source + " with " + std::string(to_string(scene->accel_config.type)) + ")";
            state.accel = scene->accel_config;  // the panels show what is built
        }
        return;
    }
    set_scene(state, std::move(**result), keep_camera_on_load);
}

void Session::set_scene(AppState& state, std::shared_ptr<const LoadedScene> loaded, bool keep_camera) {
    scene = std::move(loaded);
    ++scene_generation;
    message.clear();
    state.scene = scene->source;
    state.accel = scene->accel_config;
    if (!keep_camera || !state.camera) {
        state.camera = default_camera(scene->bounds);  // its direction; draw_frame fits the distance
        frame_pending = true;
    }
}

void Session::apply_state(AppState& state, const AppState& loaded) {
    view_panel.fill_playing = false;  // a saved state shows its own moment of the fill order
    scene_panel.playing = false;      // and of a moving scene
    // A refitting state of a moving scene's later time shows the t = 0 tree refitted:
    // a scene on screen built otherwise is loaded again.
    const bool refit_differs = scene && refit_start(loaded.scene, loaded.accel, loaded.refit_bvh).has_value() &&
                               !scene->refitted;
    const bool new_scene = !scene || loaded.scene != scene->source || refit_differs;
    const bool new_structure =
        !scene || accel_config_json(loaded.accel) != accel_config_json(scene->accel_config);
    // A load or build for an earlier state still on its way must not land after this
    // one: even when this state is what is on screen, a request replaces it.
    const bool superseding = loader.busy();
    const std::string current_scene = state.scene;
    state = loaded;
    if (new_scene) {
        state.scene = current_scene;  // until the new one has loaded
        if (auto start = refit_start(loaded.scene, loaded.accel, loaded.refit_bvh))
            loader.request_refit_from(*start, loaded.scene, loaded.accel);
        else
            loader.request(loaded.scene, loaded.accel);
        keep_camera_on_load = loaded.camera.has_value();
    } else if (new_structure || superseding) {
        rebuild_structure(state);
    }
    if (!state.camera && scene && !new_scene) {
        state.camera = default_camera(scene->bounds);
        frame_pending = true;
    }
}

void Session::notify(std::string text, bool is_error) {
    message = std::move(text);
    message_is_error = is_error;
}

std::vector<const char*> Session::pending_work() const {
    std::vector<const char*> names;
    if (loader.busy() || loader.has_result()) names.push_back("loader");
    if (presets.caption_fresh()) names.push_back("caption");
    if (ray_cast.busy() || ray_cast.has_result()) names.push_back("ray_cast");
    if (surface_cast.refining()) names.push_back("surface_cast");
    if (camera_moving) names.push_back("camera_moving");  // the full view follows once it is still
    if (view_cache.drawing_on()) names.push_back("view_picture");  // a still view's boxes, a share per frame
    if (build_stepper.busy() || build_stepper.has_result()) names.push_back("build_stepper");
    if (stepper.has_pending_work()) names.push_back("stepper");
    if (comparison.busy() || comparison.has_result()) names.push_back("comparison");
    if (two_bvhs.busy() || two_bvhs.has_result()) names.push_back("two_bvhs");
    if (scaling.busy() || scaling.has_result()) names.push_back("scaling");
    if (slice.busy()) names.push_back("slice");
    if (view_panel.fill_playing) names.push_back("fill_order");
    if (scene_panel.playing) names.push_back("time");  // a moving scene playing: the next time follows
    return names;
}

void Session::upload_to_gpu(const OverlaySettings& settings) {
    if (!scene) return;
    // The overlay depends on the scene and on the settings that select boxes
    // (not on show_structure or mesh_opacity, which only change how it is drawn).
    OverlaySettings key = settings;
    key.show_structure = overlay_settings.show_structure;
    key.mesh_opacity = overlay_settings.mesh_opacity;
    if (overlay_generation != scene_generation || !(key == overlay_settings)) {
        const CheckedStructureFile* file = scene->structure_file.get();
        overlay = file && !file->check.valid() ? make_file_overlay(*file->file, file->check, settings)
                                               : make_structure_overlay(*scene->accel, settings);
        if (!overlay_boxes) overlay_boxes = std::make_unique<BoxBuffer>();
        if (!overlay_quads) overlay_quads = std::make_unique<ColouredBuffer>();
        overlay_boxes->upload(overlay.boxes);
        overlay_quads->upload_quads(overlay.quads);
        overlay_generation = scene_generation;
        overlay_settings = settings;
    }
    if (uploaded_generation == scene_generation) return;
    // An earlier scene's mesh copy goes; this scene's is made if a frame rasterizes it.
    if (mesh_generation != scene_generation) mesh_buffer.reset();
    if (!bounds_buffer) bounds_buffer = std::make_unique<BoxBuffer>();
    std::vector<BoxInstance> bounds;
    if (!scene->bounds.empty()) bounds.push_back({scene->bounds.lo, scene->bounds.hi, Rgba8{110, 160, 240, 255}});
    bounds_buffer->upload(bounds);
    uploaded_generation = scene_generation;
}

MeshBuffer& Session::mesh_for_raster() {
    if (!mesh_buffer || mesh_generation != scene_generation) {
        if (!mesh_buffer) mesh_buffer = std::make_unique<MeshBuffer>();
        mesh_buffer->upload(*scene->mesh);
        mesh_generation = scene_generation;
    }
    return *mesh_buffer;
}

}  // namespace accelviz
