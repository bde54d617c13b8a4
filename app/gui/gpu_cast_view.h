#pragma once
/// The split view's right half cast by the GPU (View > Ray cast by: GPU): the binary
/// BVH traversed by the compute shader (app/gl/gpu_ray_caster.h) for the view's camera,
/// shown shaded or as a heat map of each invocation's loop iterations (nodes visited),
/// triangle tests or deepest stack. GL work, so it runs on the UI thread: a new cast only
/// once the camera is still (the last picture stays while it moves).

#include <memory>
#include <optional>
#include <string>

#include "app/gl/gpu_ray_caster.h"
#include "app/gl/texture.h"
#include "app/gui/app_state.h"
#include "app/gui/scene_loader.h"
#include "core/render/views.h"

namespace accelviz {

class GpuCastView {
public:
    /// Casts the view if the scene, camera or size changed and `still` (or nothing is
    /// shown yet), then makes the texture for `view.right_view` (context current).
    /// Returns false, with error(), when the GPU cannot cast this scene (below OpenGL
    /// 4.3, or not a binary BVH): the CPU's picture is shown instead.
    bool update(const ViewSettings& view, const std::shared_ptr<const LoadedScene>& scene, const CameraParams& camera,
                int width, int height, bool still);
    /// Lets go of the scene and picture (the view is not shown): the GPU's copy of a
    /// big scene stays no longer than it is needed.
    void release() {
        uploaded_.reset();
        shown_.reset();
        cast_of_ = Key{};
    }
    const Texture* texture() const { return texture_.get(); }
    const std::optional<GpuCast>& shown() const { return shown_; }
    const HeatScale& heat_scale_shown() const { return heat_scale_; }
    const std::string& error() const { return error_; }
    /// True when the picture shown is of another camera or size than the last asked for.
    bool stale() const { return stale_; }
    /// "4.5 (Core Profile) Mesa ..., llvmpipe ...": the device that cast.
    const std::string& device() const { return device_; }

private:
    struct Key {
        const LoadedScene* scene = nullptr;
        CameraParams camera;
        int width = 0, height = 0;
        bool operator==(const Key&) const = default;
    };
    std::unique_ptr<GpuRayCaster> caster_;
    std::shared_ptr<const LoadedScene> uploaded_;  ///< whose BVH the GPU holds
    Key cast_of_;
    std::optional<GpuCast> shown_;
    std::unique_ptr<Texture> texture_;
    RightView texture_view_ = RightView::RayCast;
    bool texture_dirty_ = false;
    HeatScale heat_scale_;
    std::string error_, device_;
    bool stale_ = false;
};

}  // namespace accelviz
