#pragma once
/// The nearest-point stepper's model, as plain data (no GL): a query point's search
/// (core/query/nearest_point.h) recorded once through the structure on screen, each
/// step the replay of its events (core/traversal/replay.h), and what the 3D view
/// draws for a step: the query point q, the sphere around q whose radius is the best
/// distance so far (it shrinks as nearer triangles are found, and a box wholly
/// outside it is skipped with its subtree: the lecture's early termination, with
/// distances in place of a ray's t), the nearest point so far, and the nodes visited,
/// waiting on the stack and skipped.

#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/query/nearest_point.h"
#include "core/stepper/stepper.h"
#include "core/traversal/replay.h"
#include "core/util/expected.h"

namespace accelviz {

/// One query point's search through one structure, recorded with RecordingObserver
/// by the same search `query --nearest` runs. Every event's t is a distance from q.
struct SteppedNearest {
    Vec3d query;
    std::string structure;  ///< Accelerator::name()
    std::vector<TraversalEvent> events;
    NearestPoint result;
};

/// The search from `query` through `accel` (built over `mesh`); an error for a
/// structure without one (has_nearest_search()).
Expected<SteppedNearest> record_nearest(const Accelerator& accel, const Mesh& mesh, Vec3d query);

/// Where the query point starts in a scene whose box is `bounds`: in front of the box
/// (+z, where the default camera looks from), off centre, so the nearest point is on
/// the mesh's outside and the line to it is seen from the side.
Vec3d default_query_point(const Aabb& bounds);

/// A sentence for a student about event `e`; `after`: the state just after it.
std::string explain_nearest_event(const TraversalEvent& e, const StepState& after);

/// One short line for the event list, distances as d: "visit node 4  d=0.21".
std::string describe_nearest_event(const TraversalEvent& e);

/// The geometry of the state `s` (replay(r.events, s.steps)). At most
/// `max_triangles` measured triangles are drawn (the most recent).
DebugGeometry nearest_geometry(const SteppedNearest& r, const StepState& s, const NodeBoxes& boxes, const Mesh& mesh,
                               size_t max_triangles = 2000);

}  // namespace accelviz
