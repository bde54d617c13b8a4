#include "app/gui/gpu_cast_view.h"

#include "app/platform/gl_lookup.h"

namespace accelviz {

bool GpuCastView::update(const ViewSettings& view, const std::shared_ptr<const LoadedScene>& scene,
                         const CameraParams& camera, int width, int height, bool still) {
    if (!scene || width <= 0 || height <= 0) return false;
    const Bvh* bvh = structure_if<Bvh>(*scene->accel);
    if (!bvh) {
        error_ = "the GPU traverses the binary BVH: choose bvh with 2 children per node";
        return false;
    }
    if (scene->accel_config.triangle_test != TriangleTestKind::MollerTrumbore) {
        error_ = "the GPU tests triangles by Moller-Trumbore: choose mt";
        return false;
    }
    if (!caster_) {
        auto created = GpuRayCaster::create();
        if (!created) {
            error_ = created.error();
            return false;
        }
        caster_ = std::move(*created);
        device_ = gl_description();
    }
    error_.clear();
    if (uploaded_ != scene) {
        if (auto err = caster_->upload(*bvh)) {
            error_ = err->message;
            uploaded_.reset();
            shown_.reset();
            return false;
        }
        uploaded_ = scene;
        shown_.reset();  // (another scene's picture)
    }
    const Key key{scene.get(), camera, width, height};
    stale_ = !(key == cast_of_);
    if (stale_ && (still || !shown_)) {
        shown_ = caster_->cast(Camera(camera, width, height));
        cast_of_ = key;
        stale_ = false;
        texture_dirty_ = true;
    }
    if (!shown_) return false;
    if (texture_dirty_ || view.right_view != texture_view_) {
        if (!texture_) texture_ = std::make_unique<Texture>();
        const std::vector<uint32_t>* counts = view.right_view == RightView::HeatNodes   ? &shown_->iterations
                                              : view.right_view == RightView::HeatTris  ? &shown_->tests
                                              : view.right_view == RightView::HeatStack ? &shown_->stack_depth
                                                                                        : nullptr;
        if (counts) {
            heat_scale_ = heat_scale(*counts, 0);
            texture_->upload(heat_colours(*counts, shown_->width, shown_->height, heat_scale_));
        } else {
            texture_->upload(shown_->colour);
        }
        texture_view_ = view.right_view;
        texture_dirty_ = false;
    }
    return true;
}

}  // namespace accelviz
