#pragma once
/// The scaling panel: the lecture's last slide measured in the window. The scene's
/// mesh repeated 1, 2, 4, ... times (core/measure/scaling.h), each scene rasterized
/// by OpenGL and by the CPU z-buffer and ray cast through the structures chosen, the
/// frame times on log-log axes (the chart `render --view scaling` draws).
///
/// The measuring runs on a worker with a progress bar and Cancel, except OpenGL's
/// frames: they must be drawn in the window's context, on the UI thread, so the
/// worker asks for each one and waits; update() draws one per window frame (the
/// window pauses for that frame: at 10M triangles on llvmpipe, about a second).

#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "app/gl/raster_timer.h"
#include "app/gl/texture.h"
#include "app/gui/app_state.h"
#include "app/gui/latest_job.h"
#include "app/gui/scene_loader.h"
#include "core/measure/scaling.h"

namespace accelviz {

class ScalingPanel {
public:
    ScalingPanel() = default;
    /// Cancels a measurement under way (the worker is then joined).
    ~ScalingPanel();
    ScalingPanel(const ScalingPanel&) = delete;
    ScalingPanel& operator=(const ScalingPanel&) = delete;

    /// Once per frame on the UI thread, before the frame is drawn: when `shown`, starts
    /// measuring a mesh not measured yet (again on the button) with frames of the 3D
    /// view's size, draws the OpenGL frame
    /// the worker waits for, and takes a finished measurement. Not shown: a measurement
    /// under way is cancelled. `wait`: block until it is done, drawing OpenGL's frames
    /// meanwhile (headless renders).
    void update(const AppState& state, const std::shared_ptr<const LoadedScene>& scene, Renderer& renderer,
                int view_width, int view_height, bool shown, bool wait);
    /// The panel's contents (inside a window the caller opened): the settings, the
    /// progress, the chart `width` wide and its last scene's figures. `lecture`:
    /// without the explanations (the caption gives them).
    void draw(AppState& state, float width, bool lecture);

    bool busy() const { return job_.busy(); }
    bool has_result() const { return job_.has_result(); }
    void set_on_finished(const std::function<void()>& callback) { job_.on_finished = callback; }
    /// Called on the worker when it asks for an OpenGL frame (e.g. to wake up a window
    /// waiting for events, so that update() draws it soon). Set before the first update.
    std::function<void()> on_frame_wanted;
    /// The last measurement (null before the first finishes).
    const ScalingResult* measured() const { return result_ && result_->scaling ? &*result_->scaling : nullptr; }

    /// Frames per figure (3; tests take fewer).
    int repeat = 3;

private:
    struct Result {
        ScalingSettings settings;
        std::optional<ScalingResult> scaling;
        std::string error;
    };
    /// OpenGL's frame the worker waits for: asked for by the worker, drawn by update().
    struct GlFrameRequest {
        std::mutex mutex;
        std::condition_variable answered;
        const Mesh* mesh = nullptr;  ///< non-null: a frame is asked for
        std::optional<Camera> camera;
        std::optional<double> ms;  ///< the answer
        std::string step;          ///< what the worker does now (for the panel)
    };
    void start(const ScalingSettings& settings, std::shared_ptr<const LoadedScene> scene, int width, int height,
               const std::string& gl_name);
    void cancel();
    void take_finished();
    /// Draws the frame asked for, if any (UI thread); true if one was drawn.
    bool serve_gl_frame(Renderer& renderer);
    void draw_chart(const ScalingResult& r, float width);

    LatestJob<Result> job_;
    std::weak_ptr<const Mesh> requested_mesh_;  ///< the mesh last measured (expired: none)
    std::optional<Result> result_;              ///< the last successful measurement
    std::string error_;                         ///< the last measurement's error, if it failed
    std::shared_ptr<WorkProgress> progress_;
    std::shared_ptr<GlFrameRequest> gl_;
    std::unique_ptr<RasterTimer> timer_;  ///< while measuring: the mesh on the GPU
    bool measure_again_ = false;          ///< the button was pressed
    std::unique_ptr<Texture> chart_texture_;
    uint64_t result_generation_ = 0;  ///< counts the results taken
    uint64_t charted_generation_ = 0;  ///< the result chart_texture_ shows, at charted_width_
    int charted_width_ = 0, chart_height_ = 0, charted_text_scale_ = 0;
};

}  // namespace accelviz
