#include "app/gui/surface_cast.h"

#include <chrono>

#include "app/gl/view3d.h"
#include "core/render/ray_caster.h"

namespace accelviz {

struct SurfaceCast::Result {
    Key key;
    std::shared_ptr<const LoadedScene> scene;  ///< keeps key.scene alive
    Image colour;
    std::vector<float> depth;  ///< depth-buffer values, top row first
    double milliseconds = 0;
    bool cancelled = false;
};

SurfaceCast::SurfaceCast() { job_.keep_superseded = true; }

void SurfaceCast::request(const std::shared_ptr<const LoadedScene>& scene, uint64_t scene_generation,
                          const CameraParams& camera, int width, int height, bool wait, bool full,
                          const LightSettings& light) {
    if (!scene || width <= 0 || height <= 0) return;
    const Key key{scene_generation, camera, width, height, full ? 1 : 2, light};
    if (key == requested_) {
        if (wait) job_.wait();
        return;
    }
    // A full picture under way is not wanted any more; a quarter one is let finish
    // (it is quick, and shown until a newer one is).
    if (cancel_ && requested_.divisor == 1) cancel_->cancel();
    requested_ = key;
    cancel_ = std::make_shared<WorkProgress>();
    job_.submit([key, scene, cancel = cancel_] {
        auto r = std::make_shared<Result>();
        r->key = key;
        r->scene = scene;
        const int w = (key.width + key.divisor - 1) / key.divisor, h = (key.height + key.divisor - 1) / key.divisor;
        RayCastOptions options;
        options.cancel = cancel.get();
        const std::optional<Lighting> lighting = lighting_for(key.light, *scene->mesh, scene->bounds);
        options.lighting = lighting ? &*lighting : nullptr;
        const auto start = std::chrono::steady_clock::now();  // the cast alone (auto compares it with the raster)
        Frame frame = ray_cast(*scene->accel, *scene->mesh, Camera(key.camera, w, h), options);
        r->milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        r->cancelled = cancel->cancelled();
        if (r->cancelled) return r;
        r->depth = ray_t_image_to_depth(make_view3d(key.camera, ViewRect{0, 0, w, h}, scene->bounds), frame.depth);
        r->colour = std::move(frame.colour);
        return r;
    });
    if (wait) job_.wait();
}

bool SurfaceCast::update_textures() {
    if (auto taken = job_.take(); taken && *taken && !(*taken)->cancelled) {
        const Result& r = **taken;
        if (!colour_) colour_ = std::make_unique<Texture>();
        if (!depth_) depth_ = std::make_unique<Texture>();
        colour_->upload(r.colour);  // nearest, as the depth is sampled: no fringe at silhouettes
        depth_->upload_floats(r.depth.data(), r.colour.width, r.colour.height);
        shown_ = r.key;
        shown_ms_ = r.milliseconds;
        if (r.key.divisor > 1) ++quarter_pictures_;
        if (measured_scene_ != r.key.scene) full_ms_ = 0;
        measured_scene_ = r.key.scene;
        if (r.key.divisor == 1 || full_ms_ == 0)
            full_ms_ = r.milliseconds * double(r.key.divisor) * double(r.key.divisor);
    }
    return shown_ && colour_ && !colour_->empty();
}

void SurfaceCast::cancel() {
    if (cancel_) cancel_->cancel();
    requested_ = Key{};
}

void SurfaceCast::release() {
    cancel();
    shown_.reset();
}

}  // namespace accelviz
