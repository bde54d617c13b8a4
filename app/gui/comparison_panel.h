#pragma once
/// The comparison panel: the lecture's table of structures (grid / KD tree / BVH,
/// with naive and the octree) filled with numbers measured for the scene and camera
/// on screen, and the amortization chart (total time = build + rays x time per
/// ray, against the number of rays; where each structure has paid for itself).
/// The measuring (core/measure: every structure built and traced on one thread)
/// runs on a worker with a progress bar and Cancel; the panel shows the last
/// result and says when the camera or the view's size has changed since.

#include <atomic>
#include <memory>
#include <optional>
#include <string>

#include "app/gui/app_state.h"
#include "app/gui/latest_job.h"
#include "app/gui/scene_loader.h"
#include "core/measure/comparison.h"

namespace accelviz {

class ComparisonPanel {
public:
    ComparisonPanel() = default;
    /// Cancels a measurement under way (the worker is then joined).
    ~ComparisonPanel();
    ComparisonPanel(const ComparisonPanel&) = delete;
    ComparisonPanel& operator=(const ComparisonPanel&) = delete;

    /// Once per frame on the UI thread: when `shown` (open and on screen), starts
    /// measuring a mesh not measured yet (the camera and view size of the moment; again
    /// on the button), and takes a finished measurement. Not shown: a measurement under
    /// way is cancelled (the next showing measures again). `wait`: block until it is
    /// done (headless renders).
    void update(const AppState& state, const std::shared_ptr<const LoadedScene>& scene, int view_width,
                int view_height, bool shown, bool wait);
    /// The panel's contents (inside a window the caller opened): the progress or
    /// the table, then the chart, `width` wide. `lecture`: without the explanations
    /// (the caption gives them), so that the chart has the room.
    void draw(float width, bool lecture);

    bool busy() const { return job_.busy(); }
    bool has_result() const { return job_.has_result(); }
    void set_on_finished(const std::function<void()>& callback) { job_.on_finished = callback; }
    /// The last measurement (null before the first finishes).
    const StructureComparison* measured() const { return result_ ? &*result_->comparison : nullptr; }

    /// How the panel measures (its progress and row are set per measurement). Tests
    /// put a clock that ticks here, for golden images.
    MeasureOptions options;

private:
    /// What a measurement is of: the mesh (not the scene: a new structure over the same
    /// mesh changes nothing here), the camera and the view's size.
    struct Key {
        const Mesh* mesh = nullptr;
        CameraParams camera;
        int width = 0, height = 0;
        bool operator==(const Key&) const = default;
    };
    struct Result {
        Key key;
        std::shared_ptr<const LoadedScene> scene;  ///< keeps key.mesh alive
        std::optional<StructureComparison> comparison;
        std::string error;
    };
    void start(const Key& key, std::shared_ptr<const LoadedScene> scene);
    void cancel();
    void take_finished();
    void draw_table(const StructureComparison& c, bool lecture) const;
    void draw_chart(const StructureComparison& c, float width, bool lecture) const;

    LatestJob<Result> job_;
    /// The mesh last asked for; expired (or null) when none is, so that a new mesh at a
    /// freed one's address still counts as new.
    std::weak_ptr<const Mesh> requested_mesh_;
    std::weak_ptr<const CheckedStructureFile> requested_file_;  ///< the structure file (a load of it) measured beside ours
    Key shown_view_;                ///< the view of the last update, to tell when it changed
    std::optional<Result> result_;  ///< the last successful measurement (kept when a later one fails)
    std::string error_;             ///< the last measurement's error, if it failed
    std::shared_ptr<WorkProgress> progress_;
    std::shared_ptr<std::atomic<int>> row_;
    bool measure_again_ = false;  ///< the button was pressed
};

}  // namespace accelviz
