#include "app/gui/ray_cast_view.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/render/rasterizer.h"
#include "core/render/ray_caster.h"
#include "core/render/views.h"

namespace accelviz {

void RayCastView::request(const std::shared_ptr<const LoadedScene>& scene, const CameraParams& camera, int width,
                          int height, bool wait, bool raster, bool history, const LightSettings& light) {
    if (!scene || width <= 0 || height <= 0) return;
    // The fill order's history only for the lecture's small scenes (kFillOrderMaxTriangles).
    history = history && scene->mesh->triangle_count() <= kFillOrderMaxTriangles;
    const Key key{scene.get(), camera, width, height, raster || history, history, light};
    if (key == requested_) {
        if (wait) job_.wait();
        return;
    }
    requested_ = key;
    if (cancel_) cancel_->cancel();  // the older cast is not wanted any more
    cancel_ = std::make_shared<WorkProgress>();
    job_.submit([key, scene, cancel = cancel_] {
        const auto start = std::chrono::steady_clock::now();
        RayCastOptions options;
        options.count_work = true;  // heat maps and the work label
        options.cancel = cancel.get();
        const std::optional<Lighting> lighting = lighting_for(key.light, *scene->mesh, scene->bounds);
        options.lighting = lighting ? &*lighting : nullptr;
        Result r;
        r.key = key;
        r.scene = scene;
        r.frame = ray_cast(*scene->accel, *scene->mesh, Camera(key.camera, key.width, key.height),
                           options);
        r.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        r.cancelled = cancel->cancelled();
        if (r.cancelled) return r;
        // The depth scale both grey images share: the nearest and farthest hit of either.
        auto widen = [&r](const std::vector<float>& depth) {
            for (float t : depth)
                if (std::isfinite(t)) {
                    r.t_near = std::min(r.t_near, t);
                    r.t_far = std::max(r.t_far, t);
                }
        };
        r.t_near = INFINITY;
        r.t_far = 0;
        widen(r.frame.depth);
        if (key.raster) {
            const auto raster_start = std::chrono::steady_clock::now();
            r.raster = rasterize(*scene->mesh, Camera(key.camera, key.width, key.height), &r.raster_work,
                                 key.history ? &r.raster_history : nullptr);
            r.raster_milliseconds =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - raster_start).count();
            widen(r.raster.depth);
        }
        if (!(r.t_near <= r.t_far)) r.t_near = r.t_far = 0;
        return r;
    });
    if (wait) job_.wait();
}

void RayCastView::update_texture(const ViewSettings& view) {
    bool changed = false;
    auto result = job_.take();
    if (result && result->cancelled) result.reset();  // a partial picture: dropped (requested_ was reset)
    if (result) {
        shown_ = std::move(*result);
        changed = true;
        const Frame& f = shown_->frame;
        if (heat_mesh_ != shown_->scene->mesh.get()) {  // another mesh: the remembered scale starts again
            heat_mesh_ = shown_->scene->mesh.get();
            heat_max_nodes_ = heat_max_tests_ = 0;
        }
        for (uint32_t c : f.nodes) heat_max_nodes_ = std::max(heat_max_nodes_, double(c));
        for (uint32_t c : f.tests) heat_max_tests_ = std::max(heat_max_tests_, double(c));
    }
    if (!shown_) return;
    const Frame& f = shown_->frame;
    const bool have_raster = shown_->key.raster && shown_->raster.width == f.width;

    // The fill order: both loops stopped at the same share of their work.
    if (view.fill_order && have_raster && shown_->key.history) {
        // Made again only when a loop has got further (a frame while playing may not).
        const uint64_t triangles = fill_amount(view.fill, shown_->scene->mesh->triangle_count());
        const uint64_t pixels = fill_amount(view.fill, f.colour.pixels.size());
        if (changed || !fill_shown_ || triangles != raster_fill_.triangles || pixels != ray_fill_.pixels ||
            !texture_ || !left_texture_) {
            if (!texture_) texture_ = std::make_unique<Texture>();
            if (!left_texture_) left_texture_ = std::make_unique<Texture>();
            const Camera camera(shown_->key.camera, shown_->key.width, shown_->key.height);
            left_texture_->upload(
                raster_fill_image(shown_->raster_history, *shown_->scene->mesh, camera, triangles, &raster_fill_));
            texture_->upload(ray_cast_fill_image(f, pixels, &ray_fill_));
        }
        fill_shown_ = true;
        left_view_ = LeftView::Raster;
        texture_view_ = RightView::RayCast;
        return;
    }
    if (fill_shown_) {  // back from the fill order: the textures are made again
        fill_shown_ = false;
        changed = true;
    }

    // Right: the ray caster's picture.
    if (changed || view.right_view != texture_view_ || view.heat_same_scale != texture_same_scale_ ||
        view.heat_rays != texture_heat_rays_ || !texture_) {
        if (!texture_) texture_ = std::make_unique<Texture>();
        // The secondary rays' work when asked for and traced (else the camera rays').
        const SecondaryWork* secondary = view.heat_rays == HeatRays::Shadow       ? &f.shadow
                                         : view.heat_rays == HeatRays::Reflection ? &f.reflection
                                                                                  : nullptr;
        if (secondary && secondary->nodes.empty()) secondary = nullptr;
        heat_rays_shown_ = secondary ? view.heat_rays : HeatRays::Primary;
        const std::vector<uint32_t>& nodes = secondary ? secondary->nodes : f.nodes;
        const std::vector<uint32_t>& tests = secondary ? secondary->tests : f.tests;
        // Same scale: the largest camera-ray counts since the mesh loaded.
        const double nodes_max = view.heat_same_scale && !secondary ? heat_max_nodes_ : 0;
        const double tests_max = view.heat_same_scale && !secondary ? heat_max_tests_ : 0;
        // The pictures alone: the window writes their titles and legends in its own font.
        if (view.right_view == RightView::HeatNodes) {
            heat_scale_ = heat_scale(nodes, nodes_max);
            texture_->upload(heat_colours(nodes, f.width, f.height, heat_scale_));
        } else if (view.right_view == RightView::HeatTris) {
            heat_scale_ = heat_scale(tests, tests_max);
            texture_->upload(heat_colours(tests, f.width, f.height, heat_scale_));
        } else if (view.right_view == RightView::Depth) {
            texture_->upload(depth_grey_view(f, shown_->t_near, shown_->t_far));
        } else if (view.right_view == RightView::DepthDiff && have_raster) {
            agreement_ = compare_depths(shown_->raster, f);
            texture_->upload(depth_diff_colours(shown_->raster, f));
        } else {
            texture_->upload(f.colour);
        }
        texture_view_ = view.right_view;
        texture_same_scale_ = view.heat_same_scale;
        texture_heat_rays_ = view.heat_rays;
    }

    // Left: the CPU rasterizer's picture, when asked for.
    if (view.left_view == LeftView::OpenGl || view.left_view == LeftView::OpenGlDepth || !have_raster) {  // drawn by OpenGL
        left_view_ = LeftView::OpenGl;
        return;
    }
    if (changed || view.left_view != left_view_ || !left_texture_) {
        if (!left_texture_) left_texture_ = std::make_unique<Texture>();
        if (view.left_view == LeftView::RasterDepth)
            left_texture_->upload(depth_grey_view(shown_->raster, shown_->t_near, shown_->t_far));
        else
            left_texture_->upload(shown_->raster.colour);
        left_view_ = view.left_view;
    }
}

}  // namespace accelviz
