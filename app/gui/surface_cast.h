#pragma once
/// "Draw with: ray cast": the 3D view's mesh drawn by the CPU ray caster instead of
/// OpenGL's rasterizer. A ray per pixel through the current structure (core's
/// ray_cast, the camera contract); its colour is shown and its hit distances are
/// written to the z-buffer (Renderer::draw_image_with_depth), so the structure
/// overlay OpenGL draws on top is hidden behind the surface as over the rasterized
/// mesh. The lecture's last slide on screen: rasterization touches every triangle
/// each frame; a ray through a hierarchy touches a few nodes, whatever the mesh.
///
/// Progressive: while the camera moves, a quarter of the pixels (half the width and
/// half the height) is cast and stretched over the view; once it is still, every
/// pixel (the caller says which: Session's camera motion). The casts run on a worker that keeps
/// superseded results (an older picture beats none while the camera keeps moving);
/// the UI thread never waits (headless renders and bench-view do).

#include <cstdint>
#include <memory>
#include <optional>

#include "app/gl/texture.h"
#include "app/gui/app_state.h"
#include "app/gui/latest_job.h"
#include "app/gui/scene_loader.h"
#include "core/render/camera.h"

namespace accelviz {

class SurfaceCast {
public:
    /// What a cast was made of; a new cast is needed when it changes.
    struct Key {
        uint64_t scene = 0;  ///< the Session's scene generation (a new scene is another, whatever its address)
        CameraParams camera;
        int width = 0, height = 0;  ///< the view's pixels
        int divisor = 1;            ///< 1: every pixel; 2: half the width and half the height
        LightSettings light;        ///< the ray caster's light (shadows, reflections)
        bool operator==(const Key&) const = default;
    };

    SurfaceCast();
    ~SurfaceCast() { cancel(); }

    /// Asks for a picture of the view (every frame while the ray caster draws the
    /// mesh; UI thread). `wait`: block until it is done (headless, bench-view);
    /// `full`: every pixel (the camera is still), else a quarter of them.
    void request(const std::shared_ptr<const LoadedScene>& scene, uint64_t scene_generation, const CameraParams& camera,
                 int width, int height, bool wait, bool full, const LightSettings& light = {});
    /// Takes a finished cast into the textures (GL thread). True when a picture is
    /// there to draw: the last one stays up (of an older camera or scene) until the
    /// next is done.
    bool update_textures();
    const Texture& colour() const { return *colour_; }  ///< valid once update_textures returned true
    const Texture& depth() const { return *depth_; }
    /// What the textures show (none before the first cast finishes).
    const std::optional<Key>& shown() const { return shown_; }
    /// How many quarter pictures (the camera moving) have been shown so far.
    int quarter_pictures_shown() const { return quarter_pictures_; }
    /// How long the shown picture took to cast, in ms.
    double shown_milliseconds() const { return shown_ms_; }
    /// The last measured time of a full picture of the scene's view, in ms (a quarter
    /// picture's time x 4 until a full one has finished); 0: not measured yet.
    double full_cast_milliseconds(uint64_t scene_generation) const {
        return scene_generation == measured_scene_ ? full_ms_ : 0;
    }

    /// Stops a cast under way (the ray caster is no longer drawing the mesh).
    void cancel();
    /// cancel(), and forgets the picture shown (the ray caster no longer draws the mesh).
    void release();
    bool busy() const { return job_.busy(); }
    bool has_result() const { return job_.has_result(); }
    /// More frames are needed: a cast runs or waits to be taken, or the picture shown
    /// is a quarter one (the full one follows once the camera is still).
    bool refining() const { return busy() || has_result() || (requested_.scene != 0 && requested_.divisor != 1); }
    void set_on_finished(std::function<void()> callback) { job_.on_finished = std::move(callback); }

private:
    struct Result;
    std::shared_ptr<WorkProgress> cancel_;      ///< the newest cast's
    LatestJob<std::shared_ptr<Result>> job_;
    Key requested_;
    std::optional<Key> shown_;
    double shown_ms_ = 0;
    int quarter_pictures_ = 0;
    std::unique_ptr<Texture> colour_, depth_;  ///< made at the first picture (a Session may have no GL)
    uint64_t measured_scene_ = 0;
    double full_ms_ = 0;
};

}  // namespace accelviz
