#include "app/gui/ray_cast_view.h"

#include <chrono>

#include "core/render/ray_caster.h"
#include "core/render/views.h"

namespace accelviz {

bool RayCastView::Key::operator==(const Key& o) const {
    auto same = [](Vec3d a, Vec3d b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
    return scene == o.scene && width == o.width && height == o.height && same(camera.eye, o.camera.eye) &&
           same(camera.target, o.camera.target) && same(camera.up, o.camera.up) && camera.fov_deg == o.camera.fov_deg;
}

void RayCastView::request(const std::shared_ptr<const LoadedScene>& scene, const CameraParams& camera, int width,
                          int height, bool wait) {
    if (!scene || width <= 0 || height <= 0) return;
    const Key key{scene.get(), camera, width, height};
    if (key == requested_) {
        if (wait) job_.wait();
        return;
    }
    requested_ = key;
    job_.submit([key, scene] {
        const auto start = std::chrono::steady_clock::now();
        RayCastOptions options;
        options.count_work = true;  // heat maps and the work label
        Result r;
        r.key = key;
        r.scene = scene;
        r.frame = ray_cast(*scene->accel, make_triangles(*scene->mesh), Camera(key.camera, key.width, key.height),
                           options);
        r.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        return r;
    });
    if (wait) job_.wait();
}

void RayCastView::update_texture(const std::string& right_view) {
    bool changed = false;
    if (auto result = job_.take()) {
        shown_ = std::move(*result);
        changed = true;
    }
    if (!shown_ || (!changed && right_view == texture_view_ && texture_)) return;
    if (!texture_) texture_ = std::make_unique<Texture>();
    const Frame& f = shown_->frame;
    if (right_view == "heat-nodes")
        texture_->upload(heat_view(f.nodes, f.width, f.height, "Nodes / cells visited per pixel", 0));
    else if (right_view == "heat-tris")
        texture_->upload(heat_view(f.tests, f.width, f.height, "Triangle tests per pixel", 0));
    else
        texture_->upload(f.colour);
    texture_view_ = right_view;
}

}  // namespace accelviz
