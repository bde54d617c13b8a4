#pragma once
/// The inside/outside slice in the 3D view (View > Inside / outside slice): the
/// plane of ViewSettings::slice_* across the scene, its points coloured by the
/// ray-parity vote (core/query/inside_slice.h), computed on a worker through the
/// structure on screen and drawn as translucent quads, depth-tested with the scene.

#include <atomic>
#include <memory>
#include <optional>
#include <string>

#include "app/gl/renderer.h"
#include "app/gui/app_state.h"
#include "app/gui/latest_job.h"
#include "app/gui/scene_loader.h"
#include "core/query/inside_slice.h"

namespace accelviz {

/// Samples along each side of the window's slice (3 rays per sample).
inline constexpr int kWindowSliceSamples = 128;

class SliceView {
public:
    /// Asks for the slice the state shows (a new scene, structure or plane cancels the
    /// one running), takes a finished one. `wait`: headless (complete frames).
    void update(const AppState& state, const std::shared_ptr<const LoadedScene>& scene, bool wait);
    /// The slice's quads (context current, view begun); nothing until one has arrived.
    void draw_3d(Renderer& renderer);
    bool busy() const { return job_.busy() || job_.has_result(); }  ///< (a result not taken yet counts)
    /// One line for the View panel: the work of the slice shown, "computing ...", or why
    /// there is none (a structure that does not count crossings).
    const std::string& status() const { return status_; }
    /// The slice shown (null before the first has arrived, or after an error).
    const InsideSlice* shown() const { return shown_ ? shown_.get() : nullptr; }

private:
    struct Result {
        std::shared_ptr<const LoadedScene> scene;
        SliceSpec spec;
        std::shared_ptr<const InsideSlice> slice;
        std::string error;
        double ms = 0;
    };
    void take(const Result& done);

    LatestJob<Result> job_;
    std::shared_ptr<const LoadedScene> requested_scene_;
    std::optional<SliceSpec> requested_spec_;
    std::shared_ptr<std::atomic<bool>> cancel_;  ///< the running request's
    std::shared_ptr<const InsideSlice> shown_;
    std::string status_;
    std::unique_ptr<ColouredBuffer> quads_;
    bool dirty_ = false;
};

}  // namespace accelviz
