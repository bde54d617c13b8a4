#pragma once
/// "Raster vs ray cast": the 3D view split in two. The left half is the live
/// OpenGL view (rasterized, z-buffer); the right half shows the CPU ray caster's
/// picture of exactly the same camera and size, through the current structure
/// (core's ray_cast with the camera contract), as a texture: the shaded image,
/// or a heat map of the nodes visited or triangles tested per pixel.
///
/// The ray cast runs on a worker (LatestJob): while the camera moves, the last
/// finished picture stays up (marked as updating), and only the newest camera
/// is cast.

#include <memory>
#include <optional>
#include <string>

#include "app/gl/renderer.h"
#include "app/gl/texture.h"
#include "app/gui/app_state.h"
#include "app/gui/latest_job.h"
#include "app/gui/scene_loader.h"
#include "core/render/fill_order.h"
#include "core/render/frame.h"
#include "core/render/rasterizer.h"
#include "core/render/views.h"

namespace accelviz {


class RayCastView {
public:
    /// What a cast was made of; a new cast is needed when it changes.
    struct Key {
        const LoadedScene* scene = nullptr;
        CameraParams camera;
        int width = 0, height = 0;
        bool raster = false;   ///< the core CPU rasterizer runs too
        bool history = false;  ///< and records its writes (the fill-order replay)
        LightSettings light;   ///< the ray caster's light (shadows, reflections)
        bool operator==(const Key&) const = default;
    };
    struct Result {
        Key key;
        std::shared_ptr<const LoadedScene> scene;  ///< keeps key.scene alive
        Frame frame;
        double milliseconds = 0;
        Frame raster;             ///< key.raster: the CPU rasterizer's frame of the same camera
        RasterStats raster_work;
        RasterHistory raster_history;  ///< key.history: every z-buffer write, for the fill order
        double raster_milliseconds = 0;
        float t_near = 0, t_far = 0;  ///< the depth scale shared by both grey images
        bool cancelled = false;       ///< stopped before the end: not shown
    };

    /// Asks for a cast of the current view if the last request differs (call
    /// every frame in split mode, on the UI thread). `wait`: block until it is
    /// done (headless renders).
    /// `raster`: run the core CPU rasterizer too (left_view other than "opengl",
    /// or a depth view on the right).
    /// `history`: the fill order is on (the rasterizer records its writes; implies `raster`).
    void request(const std::shared_ptr<const LoadedScene>& scene, const CameraParams& camera, int width, int height,
                 bool wait, bool raster = false, bool history = false, const LightSettings& light = {});
    /// Takes a finished cast and makes the textures for the views (GL thread).
    void update_texture(const ViewSettings& view);
    /// The texture (null before the first cast finishes) and what it shows.
    const Texture* texture() const { return texture_.get(); }
    /// The left half's CPU picture (null: none, or "opengl").
    const Texture* left_texture() const { return left_view_ != LeftView::OpenGl && left_texture_ ? left_texture_.get() : nullptr; }
    /// The heat maps' scale top (with same scale: the largest seen since the mesh loaded).
    double heat_max(bool nodes) const { return nodes ? heat_max_nodes_ : heat_max_tests_; }
    /// The scale of the heat map in the texture (for its legend).
    const HeatScale& heat_scale_shown() const { return heat_scale_; }
    /// Whose work the heat map shows (the camera rays' when no such secondary rays were traced).
    HeatRays heat_rays_shown() const { return heat_rays_shown_; }
    /// The fill order's counts in the textures (view.fill_order): each loop's work so far.
    const RasterFillCounts& raster_fill_shown() const { return raster_fill_; }
    const RayFillCounts& ray_fill_shown() const { return ray_fill_; }
    /// True when the textures show the fill order (the split view's fill-order mode).
    bool fill_shown() const { return fill_shown_; }
    /// How the two depths agree, when the texture is the depth difference.
    const DepthAgreement& depth_agreement_shown() const { return agreement_; }
    const std::optional<Result>& shown() const { return shown_; }
    /// Stops the cast under way at its next tile (its result, if taken, is partial);
    /// called when the split view closes. A new request cancels the older cast too.
    void cancel() {
        if (cancel_) cancel_->cancel();
        requested_ = Key{};  // the same view asked for again is cast again
    }
    ~RayCastView() { cancel(); }  // the worker (joined by job_'s destructor) then ends soon
    bool busy() const { return job_.busy(); }
    bool has_result() const { return job_.has_result(); }
    /// True when the picture shown is of another camera or size than requested.
    bool stale() const { return shown_ && !(shown_->key == requested_); }
    void set_on_finished(std::function<void()> callback) { job_.on_finished = std::move(callback); }

private:
    std::shared_ptr<WorkProgress> cancel_;  ///< the newest cast's (shared with its job)
    LatestJob<Result> job_;
    Key requested_;
    std::optional<Result> shown_;
    RightView texture_view_ = RightView::RayCast;  ///< the right_view the texture was made for
    bool texture_same_scale_ = false;
    HeatRays texture_heat_rays_ = HeatRays::Primary;  ///< the heat_rays the texture was made for
    HeatRays heat_rays_shown_ = HeatRays::Primary;    ///< whose work a heat texture shows (none traced: primary)
    std::unique_ptr<Texture> texture_;
    HeatScale heat_scale_;       ///< right_view heat-*: the texture's scale
    DepthAgreement agreement_;   ///< right_view depth-diff: the figures of the texture
    LeftView left_view_ = LeftView::OpenGl;  ///< the left_view left_texture_ was made for
    bool fill_shown_ = false;   ///< the textures are the fill order's
    RasterFillCounts raster_fill_;  ///< what the fill order's textures show (their amounts)
    RayFillCounts ray_fill_;
    std::unique_ptr<Texture> left_texture_;
    // Same scale for all structures: the largest counts since this mesh loaded.
    const void* heat_mesh_ = nullptr;
    double heat_max_nodes_ = 0, heat_max_tests_ = 0;
};

}  // namespace accelviz
