#pragma once
/// The construction stepper: the BVH build
/// replayed decision by decision; or, for a tree from a file (a student's BVH or
/// KD tree), the file's nodes in the order it numbers them
/// (core/exchange/file_tree_order.h: a recursive builder's construction order). The builder runs once with a BuildRecorder (on a
/// worker: the UI thread never builds), and its decisions become a timeline; the
/// window shows, for the decision at the scrubber, the node being split (its box,
/// its triangles, the two children's boxes and triangles in two colours) and its
/// SAH chart (core/accel/sah_chart.h), recomputed on a worker when the sliders
/// for B, C_trav or C_isect move.
///
/// Keys: Left/Right step, Home/End jump, while AppState::build_step.active (the
/// active stepper owns the arrows; the camera then orbits with the mouse only).

#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "app/gl/renderer.h"
#include "app/gui/app_state.h"
#include "app/gui/latest_job.h"
#include "app/gui/scene_loader.h"
#include "core/accel/bvh_build.h"
#include "core/accel/kd_sah_chart.h"
#include "core/accel/sah_chart.h"
#include "core/exchange/file_tree_order.h"

namespace accelviz {

/// A recorded build: the tree and its decisions, made from one scene.
struct BuildTrace {
    std::shared_ptr<const LoadedScene> scene;  ///< what it was recorded from (keeps the mesh alive)
    BvhConfig config;                          ///< the binary tree's own (clamped) build parameters
    Bvh bvh;                                   ///< the recorded build's tree (the scene's, or the one it collapsed)
    int scene_width = 2;                       ///< children per node of the scene's BVH (4, 8: collapsed from bvh)
    std::vector<BuildStep> steps;              ///< one per node, in the builder's order (no candidate lists)
    double build_ms = 0;
};

/// A tree in the exchange format, ready to step node by node: a file's (a
/// student's BVH or KD tree), or our KD tree exported, whose node numbers are the
/// order its build made them (a split makes its two children together; every node
/// comes after its parent).
struct FileOrderTrace {
    std::shared_ptr<const LoadedScene> scene;   ///< keeps the mesh (and a file's check) alive
    std::shared_ptr<const StructureFile> file;  ///< the tree stepped
    const StructureCheck* check = nullptr;      ///< a file's check (its faulty nodes); null for ours
    FileTreeOrder order;
};

/// True if the stepper walks `scene`'s tree node by node: a BVH or KD tree from a
/// file, or our KD tree (its build is not recorded decision by decision like the BVH's).
bool steps_nodes(const LoadedScene* scene);

/// The chart parameters for `settings` over a tree built with `built`.
BvhConfig chart_config(const BvhConfig& built, const BuildStepSettings& settings);

/// Records the build of `scene`'s BVH, or of the binary tree its wide BVH was
/// collapsed from (null if the scene's structure is not a BVH).
std::shared_ptr<const BuildTrace> record_build(std::shared_ptr<const LoadedScene> scene);

class BuildStepper {
public:
    BuildStepper();
    ~BuildStepper();
    BuildStepper(const BuildStepper&) = delete;
    BuildStepper& operator=(const BuildStepper&) = delete;

    /// Once per frame on the UI thread, before the panels: records the build when
    /// the scene changed (while active), takes finished work, asks for the chart
    /// of the step shown. `wait`: block until both are done (headless renders).
    void update(AppState& state, const std::shared_ptr<const LoadedScene>& scene, bool wait);
    /// The sidebar's "Construction" section: the switch, and a hint. True when the
    /// user asked for a BVH (the caller rebuilds the structure). `scene`: the one shown.
    bool draw_sidebar(AppState& state, const LoadedScene* scene);
    /// True if the Construction panel is to be drawn: the stepper is on, over our
    /// BVH build, our KD tree's nodes, or the nodes of a BVH or KD tree from a file.
    bool has_panel(const AppState& state, const LoadedScene* scene) const;
    /// The Construction panel (a fixed window at x, y of w x h): the timeline
    /// controls, the node, the SAH chart and its sliders. `view_aspect`: the 3D
    /// view's, for framing the node.
    void draw_panel(AppState& state, float x, float y, float w, float h, double view_aspect);
    /// Left/Right/Home/End (call when ImGui does not want the keyboard).
    void handle_keys(AppState& state);
    /// True if the 3D view shows the stepper's picture instead of the structure overlay.
    bool shows_3d(const AppState& state) const;
    /// The 3D part of the step shown: its triangles over the dimmed mesh, then the
    /// node's and children's boxes (GL thread, inside the 3D view).
    void draw_3d(Renderer& renderer, const MeshBuffer& mesh, int step, Rgb background);

    bool busy() const { return trace_job_.busy() || chart_job_.busy() || file_job_.busy(); }
    bool has_result() const { return trace_job_.has_result() || chart_job_.has_result() || file_job_.has_result(); }
    void set_on_finished(const std::function<void()>& callback) {
        trace_job_.on_finished = callback;
        chart_job_.on_finished = callback;
        file_job_.on_finished = callback;
    }
    const BuildTrace* trace() const { return trace_.get(); }
    /// A file's tree being stepped, and the node shown (null until computed).
    const FileOrderTrace* file_trace() const { return file_trace_.get(); }
    const FileNodeStep* file_node() const { return file_node_.get(); }
    const KdSahChart* kd_chart() const { return kd_chart_.get(); }

private:
    struct ChartKey {
        const BuildTrace* trace = nullptr;
        int step = -1;
        BvhConfig config;
        bool operator==(const ChartKey&) const = default;
    };
    struct ChartResult {
        ChartKey key;
        std::shared_ptr<const BuildTrace> trace;  ///< keeps key.trace alive
        SahChart chart;
    };
    struct FileStepResult {
        std::shared_ptr<const FileOrderTrace> trace;
        std::shared_ptr<const FileNodeStep> node;  ///< null: the tree has no nodes
        std::shared_ptr<const KdSahChart> kd_chart;  ///< our KD tree's node: its SAH chart
    };
    /// What the node shown is computed for: the step, and the costs the KD chart weighs with.
    struct FileStepKey {
        int step = -1;
        float cost_trav = 0, cost_isect = 0;
        bool operator==(const FileStepKey&) const = default;
    };
    void draw_chart(const SahChart& chart, const BuildStep& step, float width);
    void upload_step(const BuildStep& step, Rgb background);
    // A tree from a file (build_stepper.cpp, "A tree from a file").
    void update_file(AppState& state, const std::shared_ptr<const LoadedScene>& scene, bool wait);
    void release_file();
    void draw_file_panel(AppState& state, double view_aspect);
    void draw_kd_chart(const KdSahChart& chart, const FileNodeStep& node, float width);
    static FileStepResult file_step_of(const std::shared_ptr<const FileOrderTrace>& trace, const FileStepKey& key);
    void handle_file_keys(AppState& state);
    void draw_file_3d(Renderer& renderer, const MeshBuffer& mesh, Rgb background);

    LatestJob<std::shared_ptr<const BuildTrace>> trace_job_;
    const LoadedScene* trace_requested_ = nullptr;  ///< the scene recording was asked for
    std::shared_ptr<const BuildTrace> trace_;
    LatestJob<ChartResult> chart_job_;
    ChartKey chart_requested_;
    std::optional<ChartResult> chart_;

    // GPU copies of the step shown (made on the GL thread in draw_3d).
    const BuildTrace* uploaded_trace_ = nullptr;
    int uploaded_step_ = -1;
    Rgb uploaded_background_;
    std::unique_ptr<MeshBuffer> left_tris_, right_tris_;
    std::unique_ptr<BoxBuffer> boxes_;
    std::unique_ptr<ColouredBuffer> plane_;
    int shown_step_ = -1;  ///< the step draw_3d shows (clamped)

    // A tree from a file: its order (once per scene) and the node shown (per step), on a worker.
    bool file_scene_ = false;  ///< the scene's tree is stepped node by node: a file's BVH or KD tree, or our KD tree (update)
    bool from_file_ = false;   ///< ... and it comes from a file (update)
    LatestJob<FileStepResult> file_job_;
    const LoadedScene* file_requested_ = nullptr;
    FileStepKey file_step_requested_;
    std::shared_ptr<const FileOrderTrace> file_trace_;
    std::shared_ptr<const FileNodeStep> file_node_;
    std::shared_ptr<const KdSahChart> kd_chart_;
    std::shared_ptr<const FileNodeStep> uploaded_file_node_;  ///< the node the buffers hold (kept alive: compared by address)
    std::vector<std::unique_ptr<MeshBuffer>> child_tris_;
};

}  // namespace accelviz
