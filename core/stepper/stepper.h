#pragma once
/// The traversal stepper's model, as plain data (no GL): one ray recorded once
/// through a structure, and everything the stepper shows at step k computed from
/// the recording by replay (core/traversal/replay.h):
///   - the slab inspector (a box test's per-axis intervals, their intersection,
///     the verdict), recomputed with the traversal's own slab math and checked
///     against the recorded event's numbers;
///   - the triangle inspector (u, v, 1-u-v, t and why the test failed);
///   - the "debug geometry" of the step (docs/architecture.md): coloured boxes, segments,
///     triangles and labels for the 3D view;
///   - the compare table: the same ray through every structure.
/// Nothing here re-runs a traversal step by step: it reads the recorded events.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/triangle.h"
#include "core/traversal/replay.h"
#include "core/util/expected.h"

namespace accelviz {

// [SECTION] The recorded ray

/// One ray through one structure, recorded once with RecordingObserver by the
/// same traversal that renders. `events` is what the stepper steps through and
/// what `trace --json` prints.
struct SteppedRay {
    Ray ray;
    std::string structure;         ///< Accelerator::name(): "naive", "bvh", ...
    bool widened_box_test = false;  ///< the BVH's box test (core/math/box_test.h) widens the slabs
    TriangleTestKind triangle_test = TriangleTestKind::MollerTrumbore;  ///< the test the events come from
    std::vector<TraversalEvent> events;
    Hit hit;
    /// ClosestHit (camera and reflection rays), or AnyHit (a shadow ray: the walk
    /// stops at the first triangle in [t_min, t_max]; `hit` is that triangle).
    StopAt query = StopAt::ClosestHit;
};

SteppedRay record_ray(const Accelerator& accel, const Ray& ray, StopAt query = StopAt::ClosestHit);

/// The event that explains the state after `steps` events: events[steps - 1]
/// (none at step 0).
inline const TraversalEvent* event_before(const SteppedRay& r, size_t steps) {
    return steps > 0 && steps <= r.events.size() ? &r.events[steps - 1] : nullptr;
}

/// A sentence for a student: what the event did and why, e.g. "skip node 12:
/// its box starts at t = 3.2, beyond the closest hit t = 2.9". `state`: the
/// state just before or just after the event (for the closest hit a cull is
/// compared with: no event both culls and changes it).
std::string explain_event(const TraversalEvent& e, const StepState& state);

// [SECTION] Node boxes

/// The box of a node or cell named by an event, for every structure: BVH node
/// bounds, KD-tree and octree node cells (computed once from the root down),
/// grid cells (from the event's cell index) and the grid's or tree's root box.
class NodeBoxes {
public:
    NodeBoxes() = default;
    explicit NodeBoxes(const Accelerator& accel);
    /// The box the event is about (BoxTest, VisitNode, Push, Pop, Cull, Leaf,
    /// SplitPlane, EnterCell); nothing for naive or for events about triangles.
    std::optional<Aabb> of(const TraversalEvent& e) const;
    /// A tree node's box (BVH, KD, octree); the grid's box for a grid.
    std::optional<Aabb> node(uint32_t id) const;
    /// The structure's outer box (empty for naive).
    std::optional<Aabb> root() const;
    bool is_grid() const { return grid_; }
    /// A BSP node's plane inside its cell (empty for a leaf or another structure).
    const std::vector<Vec3>& split_polygon(uint32_t id) const;
    /// A BSP node's plane normal N (the plane is N.p = c; zero for a leaf or another structure).
    Vec3 plane_normal(uint32_t id) const { return id < normals_.size() ? normals_[id] : Vec3{0, 0, 0}; }

private:
    /// A wide BVH's boxes, indexed by slot (wide_bvh.h: the root 0, lane i of node n 1 + n·W + i).
    template <class Wide>
    void boxes_by_slot(const Wide& wide) {
        boxes_.assign(1 + wide.nodes.size() * size_t(Wide::kWidth), Aabb{});
        wide.for_each_box([&](uint32_t slot, const Aabb& box, uint32_t, uint32_t) { boxes_[slot] = box; });
    }

    std::vector<Aabb> boxes_;  ///< per tree node (BSP: the bounds of its cell)
    std::vector<std::vector<Vec3>> polygons_;  ///< BSP: per node, its plane inside its cell
    std::vector<Vec3> normals_;                ///< BSP: per node, its plane's normal
    bool grid_ = false;
    Aabb grid_bounds_;
    std::array<std::vector<float>, 3> planes_;  ///< grid cell boundaries
};

// [SECTION] Slab inspector

/// A box test taken apart as the lecture draws it: per axis the slab interval
/// [t_min, t_max], the intersection of the three (clipped to the ray's range)
/// and the verdict. The numbers come from the traversal's own slab math, so
/// t_enter, t_exit and hit equal the recorded event's (`agrees`).
struct SlabInspection {
    uint32_t node = 0;
    Aabb box;
    float axis_min[3] = {0, 0, 0};  ///< per axis: where the ray enters the slab (may be -inf)
    float axis_max[3] = {0, 0, 0};  ///< and leaves it (may be +inf; empty if the origin is outside a parallel slab)
    float ray_min = 0, ray_max = kInfinity;  ///< the ray's [t_min, t_max] the test starts from
    float t_enter = 0, t_exit = 0;  ///< the intersection, as the traversal reported it
    bool hit = false;
    bool widened = false;           ///< BVH: each plane's distance moved outwards by kBoxTestMargin
    bool agrees = false;            ///< t_enter, t_exit and hit equal the event's, bit for bit
    std::string verdict;            ///< one line: why it hit or missed
};

/// The inspection of a BoxTest event (nothing if the box is unknown).
std::optional<SlabInspection> inspect_box_test(const SteppedRay& r, const NodeBoxes& boxes,
                                               const TraversalEvent& box_test);

/// Why boxes are axis-aligned (the lecture's 为什么用轴对齐的包围盒): a box is six
/// planes, and where a ray o + t d crosses a plane costs
///   a general plane N·x = c:      t = (c − N·o) / (N·d)   N·o 3× 2±, N·d 3× 2±, c − N·o 1±, 1÷
///   an axis-aligned one x = x0:   t = (x0 − o_x) / d_x     1±, 1÷
/// (the slide's 2D count is 4× 1± 1÷ against 1± 1÷). The slab test computes 1/d once
/// per ray, so its ÷ is a ×: the lecture's count is kept here.
inline constexpr OperationCount kGeneralPlaneOps{6, 5, 1};
inline constexpr OperationCount kAxisPlaneOps{0, 1, 1};
inline constexpr int kBoxPlanes = 6;
/// The arithmetic of many box tests (64 bits: a frame's rays make billions).
struct BoxTestOps {
    int64_t multiplies = 0, adds = 0, divides = 0;
};
/// The arithmetic of `box_tests` box tests, each of kBoxPlanes planes costing `per_plane`.
constexpr BoxTestOps box_test_ops(uint64_t box_tests, const OperationCount& per_plane) {
    const int64_t planes = int64_t(box_tests) * kBoxPlanes;
    return {planes * per_plane.multiplies, planes * per_plane.adds, planes * per_plane.divides};
}

// [SECTION] Triangle inspector

struct TriangleInspection {
    uint32_t tri = Hit::kNoHit;
    float u = 0, v = 0, w = 0;  ///< barycentric weights of p1, p2 and p0 (w = 1 - u - v)
    float t = kInfinity;
    float t_max = kInfinity;    ///< the range the test accepted: the closest hit so far (or the ray's end)
    bool hit = false;
    std::string verdict;        ///< "hit", or which condition failed
};

/// The inspection of events[index] (a TriangleTest).
TriangleInspection inspect_triangle_test(const SteppedRay& r, size_t index);

/// The inspected triangle under both tests, on the same ray and range (the
/// inspection's t_max): where they disagree, the ray passes within rounding of an
/// edge or a vertex, and Möller–Trumbore may let it slip between two triangles.
struct TriangleTestComparison {
    TriangleTest moller_trumbore;
    TriangleTest watertight;
    bool disagree() const { return moller_trumbore.hit != watertight.hit; }
};
TriangleTestComparison compare_triangle_tests(const SteppedRay& r, const TriangleInspection& inspection,
                                              const Mesh& mesh);

// [SECTION] Debug geometry

struct DebugColour {
    uint8_t r = 255, g = 255, b = 255, a = 255;
};
struct DebugBox {
    Aabb box;
    DebugColour colour;
};
struct DebugSegment {
    Vec3 a, b;
    DebugColour colour;
};
struct DebugTriangle {
    Vec3 p[3];
    DebugColour colour;  ///< filled, translucent
};
struct DebugQuad {
    Vec3 corners[4];
    DebugColour colour;  ///< filled, translucent (a KD split plane)
};
struct DebugLabel {
    Vec3 at;
    std::string text;
    DebugColour colour;
};

/// What the 3D view draws for one step. Colours (kStepColours) are fixed so the
/// legend can name them.
struct DebugGeometry {
    std::vector<DebugBox> boxes;
    std::vector<DebugSegment> segments;
    std::vector<DebugTriangle> triangles;
    std::vector<DebugQuad> quads;
    std::vector<DebugLabel> labels;
};

/// Three short segments along the axes, crossing at p (`size` each way).
void add_cross(DebugGeometry& g, Vec3 p, float size, DebugColour c);

struct StepState;
/// The triangles tested so far in `s` (the latest `max_triangles`), filled green where
/// the test hit and red where it missed; `mesh` gives their corners.
void add_tested_triangles(DebugGeometry& g, const StepState& s, const Mesh& mesh, size_t max_triangles);

/// The palette of the step geometry (and of the panels that name it).
struct StepColours {
    DebugColour ray{200, 200, 200, 255};           ///< the whole ray
    DebugColour interval{255, 150, 30, 255};       ///< the current [t_enter, t_exit]
    DebugColour current{255, 150, 30, 255};        ///< the node/cell being worked on
    DebugColour tested_hit{90, 230, 90, 255};      ///< the box being tested: the ray enters it
    DebugColour tested_miss{240, 70, 70, 255};     ///< the box being tested: missed
    DebugColour stacked{90, 150, 255, 200};        ///< waiting on the stack
    DebugColour visited{150, 150, 170, 110};       ///< visited earlier
    DebugColour culled_missed{110, 110, 110, 200};  ///< culled: the ray misses its box
    DebugColour culled_beyond{170, 90, 190, 220};   ///< culled: starts beyond the closest hit
    DebugColour triangle_hit{60, 220, 60, 150};    ///< tested triangle, hit
    DebugColour triangle_miss{230, 60, 60, 110};   ///< tested triangle, missed
    DebugColour closest{255, 240, 60, 255};        ///< the closest hit so far
    DebugColour rejected{255, 80, 200, 255};       ///< a hit outside the current cell (not yet accepted)
    DebugColour split{80, 220, 230, 90};           ///< KD/octree split plane
    DebugColour query{255, 255, 255, 255};         ///< the nearest-point search's query point
};
inline constexpr StepColours kStepColours{};

/// The box tests made together with event `index` (a BoxTest): the run of
/// consecutive BoxTest events around it, [first, last). A wide BVH node's children
/// (4 or 8, one SIMD instruction sequence) or algorithm 2's two children; a single
/// test elsewhere. Empty if events[index] is not a box test.
struct SiblingTests {
    size_t first = 0, last = 0;
    size_t size() const { return last - first; }
};
SiblingTests sibling_box_tests(const std::vector<TraversalEvent>& events, size_t index);

/// The geometry of the state `s` (replay(r.events, s.steps)). `mesh` gives the
/// tested triangles' corners. At most `max_triangles` tested triangles are drawn
/// (the most recent), so naive on a big mesh stays cheap.
DebugGeometry step_geometry(const SteppedRay& r, const StepState& s, const NodeBoxes& boxes, const Mesh& mesh,
                            size_t max_triangles = 2000);

/// The length of ray drawn: to where it leaves the structure's box (or the
/// mesh's), at least past the closest hit.
float ray_draw_length(const SteppedRay& r, const Mesh& mesh);

// [SECTION] Compare table

/// The structures the compare table runs, built with default parameters over one mesh.
struct CompareSet {
    struct Entry {
        std::string label;  ///< "naive", "BVH alg. 1 (unordered)", ...
        std::shared_ptr<const Accelerator> accel;
    };
    std::vector<Entry> entries;
};

/// Builds naive, BVH (algorithm 1 and 2: one build, two traversals), grid, KD
/// tree and octree with their defaults. Takes a while on big meshes: call it on
/// a worker thread.
Expected<CompareSet> build_compare_set(const Mesh& mesh);

struct CompareRow {
    std::string label;
    Counters counters;
    Hit hit;                        ///< the closest-hit query's answer
    bool blocked = false;           ///< the any-hit query's answer (it names no triangle)
    bool agrees_with_naive = true;  ///< same triangle and t (any-hit: same answer) as the first row (naive)
};

/// The same ray through every entry (counting observer: cheap), by `query`.
std::vector<CompareRow> compare_ray(const CompareSet& set, const Ray& ray, StopAt query = StopAt::ClosestHit);

}  // namespace accelviz
