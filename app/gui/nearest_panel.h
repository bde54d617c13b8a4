#pragma once
/// The nearest-point stepper in the window: a panel right of the 3D view that steps
/// the search for the point on the mesh nearest to a query point q through the
/// structure on screen (naive, the binary BVH or the KD tree), event by event, and in
/// the 3D view q (dragged with the mouse), the sphere of the best distance so far
/// shrinking as the steps go on, the nearest point, and the nodes visited, waiting
/// and skipped (grey: wholly outside the sphere).
///
/// The search is recorded once (core/stepper/nearest_stepper.h: the same search
/// `query --nearest` runs); each step shown is replay(events, k).

#include <memory>
#include <optional>
#include <string>

#include "app/gl/renderer.h"
#include "app/gui/app_state.h"
#include "app/gui/debug_geometry_gl.h"
#include "app/gui/scene_loader.h"
#include "app/gui/step_playback.h"
#include "core/stepper/nearest_stepper.h"

namespace accelviz {

struct Session;

/// Naive records one event per triangle: above this many triangles the panel asks
/// for a structure instead of recording (on the UI thread) a list too long to step.
inline constexpr size_t kNearestNaiveMaxTriangles = 200000;

struct NearestPanel {
    // What is recorded: the search from the point through the scene's structure.
    std::shared_ptr<const LoadedScene> searched_scene;
    std::optional<Vec3d> searched_point;
    std::optional<SteppedNearest> search;
    std::string error;  ///< why there is no search (a structure without one)
    NodeBoxes boxes;

    // The state at the step shown, and its geometry.
    size_t shown_step = size_t(-1);
    StepState step_state;
    DebugGeometry geometry;
    bool geometry_dirty = true;
    DebugGeometryGl gl_geometry;
    StepPlayback playback{.speed = 8.0f};

    float point_edit[3] = {0, 0, 0};

    /// Before the panels: the default point, the search recorded if the scene,
    /// structure or point changed, playback, the replay to the step.
    void update(AppState& state, Session& session, double delta_seconds, bool wait);
    void handle_keys(AppState& state);
    /// The panel's contents (inside its window); `lecture`: a shorter event list.
    void draw(AppState& state, Session& session, bool lecture = false);
    void draw_3d(Renderer& renderer, float line_width);
    void draw_labels(const View3D& view) const;
};

}  // namespace accelviz
