#pragma once
/// The traversal stepper in the window: a panel on the right of the 3D
/// view that steps one ray through the current structure, event by event, and
/// the step's debug geometry drawn in the 3D view.
///
/// The ray (AppState::stepper.ray) is recorded ONCE with the recording observer
/// by the structure on screen (core/stepper: record_ray); every step shown is
/// replay(events, k), so stepping back costs what stepping forward does. The
/// compare table's structures are built on a worker thread (the UI never waits
/// for them, except headless frames, which must be complete).

#include <memory>
#include <optional>
#include <string>

#include "app/gl/renderer.h"
#include "app/gui/debug_geometry_gl.h"
#include "app/gui/app_state.h"
#include "app/gui/latest_job.h"
#include "app/gui/scene_loader.h"
#include "app/gui/step_playback.h"
#include "core/stepper/stepper.h"

namespace accelviz {

struct Session;

/// A camera that sees `ray` from the side: `camera` (from which a picked ray is
/// seen end-on, as a dot) turned 35 degrees about up and 15 degrees higher, aimed
/// at the point of the ray nearest to its target, at 0.6 times its distance.
CameraParams stepper_side_view(const CameraParams& camera, const Ray& ray);

struct StepperPanel {
    // What is recorded: the ray through the scene's structure (remade when either changes).
    std::shared_ptr<const LoadedScene> traced_scene;
    std::optional<Ray> traced_ray;
    bool traced_any_hit = false;  ///< the query `trace` was recorded by
    SteppedRay trace;
    /// The rays stepped before this one from the same pixel (a camera ray, then its
    /// reflection ray), for "Back"; emptied when another ray is picked.
    std::vector<StepperSettings> earlier_rays;
    bool following = false;  ///< the ray was just switched along the chain (not picked anew)
    NodeBoxes boxes;

    // The state at the step shown, and its geometry (remade when the step changes).
    size_t shown_step = size_t(-1);
    StepState step_state;
    DebugGeometry geometry;
    bool geometry_dirty = true;
    DebugGeometryGl gl_geometry;

    // The compare table: structures built on a worker per mesh, rows per ray.
    struct CompareBuild {
        std::shared_ptr<const Mesh> mesh;
        std::shared_ptr<const CompareSet> set;
        std::string error;
    };
    LatestJob<CompareBuild> compare_job;
    std::shared_ptr<const Mesh> compare_requested;  ///< the mesh a build was asked for
    std::optional<CompareBuild> compare;            ///< the finished build
    std::optional<Ray> compare_ray_of;              ///< the ray `compare_rows` are of
    bool compare_any_hit_of = false;                ///< ... and the query
    std::vector<CompareRow> compare_rows;

    // Playing (window only: never in a deterministic frame).
    StepPlayback playback;

    // The typed ray.
    float origin_edit[3] = {0, 0, 0};
    float dir_edit[3] = {0, 0, -1};
    std::optional<Ray> edits_of;  ///< the ray the fields were last filled from

    /// Before the panels: records the ray if the scene, structure or ray changed,
    /// advances playback, replays to the step, starts the compare build.
    /// `wait`: headless (complete frames: waits for the compare build).
    void update(AppState& state, Session& session, double delta_seconds, bool wait);
    /// Right/Left/Home/End/Space when ImGui does not want the keyboard.
    void handle_keys(AppState& state);
    /// The panel's contents (inside its window).
    /// `lecture`: for the projector, the inspectors come before the fold: no "Type a
    /// ray" section and a shorter event list.
    void draw(AppState& state, Session& session, bool lecture = false);
    /// The step's boxes, segments and triangles in the 3D view (context current, view begun).
    /// Boxes at `line_width`, the ray and its marks thicker.
    void draw_3d(Renderer& renderer, float line_width);
    /// Labels (stack entries, t values) at their 3D points, over the 3D view.
    void draw_labels(const View3D& view) const;
    /// Picks the ray through pixel (x, y) of a view `width` x `height` under `camera`.
    static void pick(AppState& state, const CameraParams& camera, int width, int height, int x, int y);

    bool has_pending_work() const { return compare_job.busy() || compare_job.has_result(); }

private:
    void draw_slab_inspector(const SlabInspection& s) const;
    void draw_sibling_tests(const SiblingTests& run, size_t current) const;
    void draw_plane_first(const TriangleInspection& t) const;
    void draw_compare();
    void draw_inspectors(const TraversalEvent* current);
    void draw_stack();
    /// Under the step counter: the hit's shadow ray and, off a mirror, its reflection
    /// ray (the ray caster's, lighting.h), to step next; and back.
    void draw_next_rays(AppState& state, const Session& session);
    static StopAt query(const AppState& state);
    void draw_ray_fields(AppState& state, Session& session);
};

}  // namespace accelviz
