#pragma once
/// The two-BVHs panel: the lecture's "two BVHs over the same 22 triangles: which is
/// better?" for the scene on screen. Two builders make the structure's BVH side by
/// side (every other parameter is the structure's); each tree is drawn as the camera
/// sees it, boxes coloured by depth and triangles by leaf, and a table gives what
/// answers the question: SAH cost and the work per ray of this view. Measured on a
/// worker (core/measure/two_bvhs.h), again whenever the scene, the parameters, the
/// camera or the view's size change.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/gui/app_state.h"
#include "app/gui/latest_job.h"
#include "app/gui/scene_loader.h"
#include "core/measure/two_bvhs.h"

namespace accelviz {

class TwoBvhsPanel {
public:
    TwoBvhsPanel() = default;
    /// Cancels a measurement under way (the worker is then joined).
    ~TwoBvhsPanel();
    TwoBvhsPanel(const TwoBvhsPanel&) = delete;
    TwoBvhsPanel& operator=(const TwoBvhsPanel&) = delete;

    /// Once per frame on the UI thread: when `shown`, measures what is on screen if
    /// that is not what was measured last, and takes a finished measurement. Not
    /// shown: a measurement under way is cancelled. `wait`: block until it is done
    /// (headless renders).
    void update(const AppState& state, const std::shared_ptr<const LoadedScene>& scene, int view_width,
                int view_height, bool shown, bool wait);
    /// The panel's contents, `width` wide (inside a window the caller opened); the
    /// builder combos edit `state`. `lecture`: without the explanations and combos.
    void draw(AppState& state, float width, bool lecture);

    bool busy() const { return job_.busy(); }
    bool has_result() const { return job_.has_result(); }
    void set_on_finished(const std::function<void()>& callback) { job_.on_finished = callback; }
    /// The last measurement (null before the first finishes).
    const TwoBvhs* measured() const { return result_ ? &*result_->trees : nullptr; }
    /// The last measurement's error ("" when it succeeded or was cancelled).
    const std::string& error() const { return error_; }

private:
    /// What a measurement is of.
    struct Key {
        const Mesh* mesh = nullptr;
        BvhConfig config;  ///< the structure's BVH parameters (its builder is not used)
        BvhTraversal traversal = BvhTraversal::Ordered;
        std::array<BvhBuilder, 2> builders{};
        CameraParams camera;
        int width = 0, height = 0;
        bool operator==(const Key&) const = default;
        /// The same trees (a new camera or view size only traces the rays again).
        bool same_trees(const Key& o) const { return mesh == o.mesh && config == o.config && builders == o.builders; }
    };
    struct Result {
        Key key;
        std::shared_ptr<const LoadedScene> scene;  ///< keeps key.mesh alive
        std::shared_ptr<const BvhPair> pair;       ///< the trees, kept for the next camera
        std::optional<TwoBvhs> trees;
        /// Per tree: the node indices drawn, shallow levels first (as many whole levels
        /// as kMaxBoxesDrawn allows), and the deepest level among them.
        std::array<std::vector<uint32_t>, 2> drawn;
        std::array<uint32_t, 2> drawn_depth{};
        /// The part of the view the pictures show, in pixels: the scene's box as the camera
        /// sees it, with a margin, within the image (the whole image if the box reaches
        /// behind the eye).
        double crop_x0 = 0, crop_y0 = 0, crop_x1 = 0, crop_y1 = 0;
        std::string error;
    };
    void start(const Key& key, std::shared_ptr<const LoadedScene> scene);
    void take_finished();
    void draw_tree(const Result& result, size_t which, float width, float height) const;
    void draw_table(const TwoBvhs& m, bool lecture) const;

    LatestJob<Result> job_;
    std::optional<Key> requested_;
    std::weak_ptr<const Mesh> requested_mesh_;  ///< expired: a new mesh at a freed one's address is new
    std::optional<Result> result_;
    std::string error_;
    std::shared_ptr<WorkProgress> progress_;
};

}  // namespace accelviz
