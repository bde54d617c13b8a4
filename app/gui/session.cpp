#include "app/gui/session.h"

namespace accelviz {

void Session::open_scene(const AppState& state, const std::string& source, bool keep_camera) {
    keep_camera_on_load = keep_camera;
    loader.request(source, state.accel);
}

void Session::take_finished_load(AppState& state) {
    std::optional<LoadResult> result = loader.take_result();
    if (!result) return;
    if (!*result) {
        // DESIGN.md, "Errors": show it, keep the previous scene.
        message = result->error();
        if (scene) message += "  (keeping " + scene->source + ")";
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

void Session::upload_to_gpu() {
    if (!scene || uploaded_generation == scene_generation) return;
    if (!mesh_buffer) mesh_buffer = std::make_unique<MeshBuffer>();
    if (!bounds_buffer) bounds_buffer = std::make_unique<BoxBuffer>();
    mesh_buffer->upload(scene->mesh);
    std::vector<BoxInstance> bounds;
    if (!scene->bounds.empty()) bounds.push_back({scene->bounds.lo, scene->bounds.hi, Rgba8{120, 170, 255, 200}});
    bounds_buffer->upload(bounds);
    uploaded_generation = scene_generation;
}

}  // namespace accelviz
