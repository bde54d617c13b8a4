#include "core/stepper/stepper.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/math/box_test.h"
#include "core/accel/brute_force.h"
#include "core/accel/bsp_tree.h"
#include "core/accel/bvh.h"
#include "core/accel/factory.h"
#include "core/accel/kd_tree.h"
#include "core/accel/octree.h"
#include "core/accel/uniform_grid.h"
#include "core/accel/wide_bvh.h"

namespace accelviz {

// [SECTION] The recorded ray

SteppedRay record_ray(const Accelerator& accel, const Ray& ray, StopAt query) {
    SteppedRay r;
    r.ray = ray;
    r.structure = accel.name();
    r.widened_box_test = accel.type() == AccelType::Bvh;
    r.triangle_test = accel.triangle_test();
    r.query = query;
    RecordingObserver recorder;
    if (query == StopAt::AnyHit) {
        accel.intersect_any(ray, recorder);
        // Every walk ends with Done, which names the triangle that blocks the ray.
        if (!recorder.events.empty() && recorder.events.back().kind == EventKind::Done && recorder.events.back().hit) {
            const TraversalEvent& done = recorder.events.back();
            r.hit = {done.tri, done.t, done.u, done.v};
        }
    } else {
        r.hit = accel.intersect_closest(ray, recorder);
    }
    r.events = std::move(recorder.events);
    return r;
}

TriangleTestComparison compare_triangle_tests(const SteppedRay& r, const TriangleInspection& inspection,
                                              const Mesh& mesh) {
    TriangleTestComparison out;
    if (inspection.tri >= mesh.triangle_count()) return out;
    Ray ray = r.ray;
    ray.t_max = inspection.t_max;
    out.moller_trumbore = intersect_triangle(mesh.triangle(inspection.tri), ray);
    out.watertight = intersect_triangle(mesh.corners(inspection.tri), ray);
    return out;
}

// [SECTION] Node boxes

NodeBoxes::NodeBoxes(const Accelerator& accel) {
    if (const Bvh* bvh = structure_if<Bvh>(accel)) {
        boxes_.reserve(bvh->nodes.size());
        for (const BvhNode& n : bvh->nodes) boxes_.push_back(n.bounds);
    } else if (const auto* wide4 = structure_if<WideBvh<4>>(accel)) {
        boxes_by_slot(*wide4);
    } else if (const auto* wide8 = structure_if<WideBvh<8>>(accel)) {
        boxes_by_slot(*wide8);
    } else if (const KdTree* kd = structure_if<KdTree>(accel)) {
        boxes_ = kd->node_boxes();
    } else if (const Octree* octree = structure_if<Octree>(accel)) {
        boxes_ = octree->node_boxes();
    } else if (const BspTree* bsp = structure_if<BspTree>(accel)) {
        boxes_ = bsp->node_shapes().cell_bounds;
        polygons_ = bsp->node_shapes().split_polygons;
        for (const BspNode& n : bsp->nodes) normals_.push_back(n.is_leaf() ? Vec3{0, 0, 0} : n.plane.normal);
    } else if (const UniformGrid* grid = structure_if<UniformGrid>(accel)) {
        grid_ = true;
        grid_bounds_ = grid->bounds;
        planes_ = grid->planes;
    }
}

std::optional<Aabb> NodeBoxes::node(uint32_t id) const {
    if (grid_) return grid_bounds_;
    if (id < boxes_.size()) return boxes_[id];
    return std::nullopt;
}

const std::vector<Vec3>& NodeBoxes::split_polygon(uint32_t id) const {
    static const std::vector<Vec3> none;
    return id < polygons_.size() ? polygons_[id] : none;
}

std::optional<Aabb> NodeBoxes::root() const {
    if (grid_) return grid_bounds_;
    if (!boxes_.empty()) return boxes_[0];
    return std::nullopt;
}

std::optional<Aabb> NodeBoxes::of(const TraversalEvent& e) const {
    switch (e.kind) {
        case EventKind::EnterCell: {
            if (!grid_) return node(e.node);
            for (int a = 0; a < 3; ++a)
                if (e.cell[a] < 0 || size_t(e.cell[a]) + 1 >= planes_[size_t(a)].size()) return std::nullopt;
            return Aabb{{planes_[0][size_t(e.cell[0])], planes_[1][size_t(e.cell[1])], planes_[2][size_t(e.cell[2])]},
                        {planes_[0][size_t(e.cell[0]) + 1], planes_[1][size_t(e.cell[1]) + 1],
                         planes_[2][size_t(e.cell[2]) + 1]}};
        }
        case EventKind::BoxTest:
        case EventKind::VisitNode:
        case EventKind::Push:
        case EventKind::Pop:
        case EventKind::Cull:
        case EventKind::Leaf:
        case EventKind::SplitPlane: return node(e.node);
        default: return std::nullopt;
    }
}

// [SECTION] Slab inspector

namespace {

const char* axis_name(int a) { return a == 0 ? "x" : a == 1 ? "y" : "z"; }

std::string format(const char* fmt, auto... args) {
    char text[256];
    std::snprintf(text, sizeof text, fmt, args...);
    return text;
}

}  // namespace

std::optional<SlabInspection> inspect_box_test(const SteppedRay& r, const NodeBoxes& boxes, const TraversalEvent& e) {
    const std::optional<Aabb> box = boxes.of(e);
    if (!box || e.kind != EventKind::BoxTest) return std::nullopt;
    SlabInspection s;
    s.node = e.node;
    s.box = *box;
    s.ray_min = r.ray.t_min;
    s.ray_max = r.ray.t_max;
    s.widened = r.widened_box_test;
    float enter, exit;
    if (r.widened_box_test) {
        // widened_slab_test (core/math/box_test.h), one axis at a time, in its order.
        const BoxTestRay ray(r.ray);
        const bool behind = r.ray.t_min < 0.0f;
        const Vec3& near_scale = behind ? ray.dir_inv : ray.near_dir_inv;
        const Vec3& far_scale = behind ? ray.dir_inv : ray.far_dir_inv;
        enter = behind ? -kInfinity : r.ray.t_min;
        exit = behind ? kInfinity : r.ray.t_max;
        for (int a = 0; a < 3; ++a) {
            s.axis_min[a] = (ray.near_plane_of(*box, a) - ray.origin[a]) * near_scale[a];
            s.axis_max[a] = (ray.far_plane_of(*box, a) - ray.origin[a]) * far_scale[a];
            enter = s.axis_min[a] > enter ? s.axis_min[a] : enter;
            exit = s.axis_max[a] < exit ? s.axis_max[a] : exit;
        }
        if (behind) {
            enter *= enter > 0.0f ? 1.0f - kBoxTestMargin : 1.0f + kBoxTestMargin;
            exit *= exit > 0.0f ? 1.0f + kBoxTestMargin : 1.0f - kBoxTestMargin;
            enter = enter > r.ray.t_min ? enter : r.ray.t_min;
            exit = exit < r.ray.t_max ? exit : r.ray.t_max;
        }
        s.hit = enter <= exit;  // Bvh::entered
    } else {
        // slab_test (core/math/aabb.h) from the ray's [t_min, t_max], as the grid, KD tree and octree call it.
        const RayPrecomp pre(r.ray);
        enter = r.ray.t_min;
        exit = r.ray.t_max;
        for (int a = 0; a < 3; ++a) {
            const SlabInterval slab = slab_interval(*box, pre, a);
            s.axis_min[a] = slab.t_min;
            s.axis_max[a] = slab.t_max;
            enter = slab.t_min > enter ? slab.t_min : enter;
            exit = slab.t_max < exit ? slab.t_max : exit;
        }
        s.hit = SlabResult{enter, exit}.hit();
    }
    s.t_enter = enter;
    s.t_exit = exit;
    auto same = [](float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); };
    s.agrees = same(s.t_enter, e.t_enter) && same(s.t_exit, e.t_exit) && s.hit == e.hit;

    // Which slab decides: the latest entry and the earliest exit (NaN bounds never decide).
    int enter_axis = -1, exit_axis = -1;
    for (int a = 0; a < 3; ++a) {
        if (s.axis_min[a] == s.t_enter) enter_axis = a;
        if (s.axis_max[a] == s.t_exit && exit_axis < 0) exit_axis = a;
    }
    if (s.hit) {
        s.verdict = format("hit: inside all three slabs for t in [%.4g, %.4g]", s.t_enter, s.t_exit);
    } else if (enter_axis >= 0 && exit_axis >= 0 && s.t_enter > s.t_exit) {
        s.verdict = format("miss: leaves the %s slab (t = %.4g) before entering the %s slab (t = %.4g)",
                           axis_name(exit_axis), s.t_exit, axis_name(enter_axis), s.t_enter);
    } else if (s.t_exit < s.ray_min || s.t_exit < 0.0f) {
        s.verdict = format("miss: the box lies behind the ray's start (t_exit = %.4g)", s.t_exit);
    } else if (s.t_enter > s.ray_max) {
        s.verdict = format("miss: the box starts after the ray's end (t_enter = %.4g)", s.t_enter);
    } else {
        s.verdict = "miss: the slabs do not overlap";
    }
    return s;
}

// [SECTION] Events in words

std::string explain_event(const TraversalEvent& e, const StepState& before) {
    const char* axis = axis_name(e.axis % 3);
    switch (e.kind) {
        case EventKind::BoxTest:
            return e.hit ? format("box test: the ray is inside node %u's box for t in [%.4g, %.4g]", e.node, e.t_enter,
                                  e.t_exit)
                         : format("box test: the ray misses node %u's box", e.node);
        case EventKind::VisitNode: return format("visit node %u, t in [%.4g, %.4g]", e.node, e.t_enter, e.t_exit);
        case EventKind::Push:
            return format("push node %u: it waits on the stack (its interval starts at t = %.4g)", e.node, e.t_enter);
        case EventKind::Pop: return format("pop node %u off the stack (t_enter = %.4g)", e.node, e.t_enter);
        case EventKind::Cull:
            if (e.reason == CullReason::MissedBox) return format("skip node %u: the ray misses its box", e.node);
            return format("skip node %u: it starts at t = %.4g, beyond the closest hit t = %.4g", e.node, e.t_enter,
                          before.closest.t);
        case EventKind::Leaf:
            return format("leaf %u: test its %u triangle%s (t in [%.4g, %.4g])", e.node, e.count,
                          e.count == 1 ? "" : "s", e.t_enter, e.t_exit);
        case EventKind::TriangleTest:
            return e.hit ? format("triangle %u: hit at t = %.4g (u = %.3g, v = %.3g)", e.tri, e.t, e.u, e.v)
                         : format("triangle %u: miss", e.tri);
        case EventKind::NewClosest: return format("closest hit so far: triangle %u at t = %.4g", e.tri, e.t);
        case EventKind::EnterCell:
            return format("walk into cell (%d, %d, %d), t in [%.4g, %.4g]", e.cell[0], e.cell[1], e.cell[2], e.t_enter,
                          e.t_exit);
        case EventKind::MailboxSkip:
            return format("triangle %u was tested in an earlier cell: skip it (mailbox)", e.tri);
        case EventKind::HitOutsideCell:
            return format("triangle %u is hit at t = %.4g, past this cell's end t = %.4g: not accepted yet", e.tri,
                          e.t, e.t_exit);
        case EventKind::SplitPlane:
            if (e.axis == kGeneralPlane)
                return format("node %u: plane N.p = %.4g, crossed at t = %.4g; the %s side comes first", e.node,
                              e.split, e.t, e.near_first ? "back" : "front");
            return format("node %u: plane %s = %.4g, crossed at t = %.4g; the %s side comes first", e.node, axis,
                          e.split, e.t, e.near_first ? "lower" : "upper");
        case EventKind::Done:
            return e.hit ? format("done: triangle %u at t = %.6g", e.tri, e.t) : std::string("done: the ray hits nothing");
    }
    return {};
}

// [SECTION] Triangle inspector

TriangleInspection inspect_triangle_test(const SteppedRay& r, size_t index) {
    TriangleInspection out;
    if (index >= r.events.size() || r.events[index].kind != EventKind::TriangleTest) return out;
    const TraversalEvent& e = r.events[index];
    out.tri = e.tri;
    out.u = e.u;
    out.v = e.v;
    out.w = 1.0f - e.u - e.v;
    out.t = e.t;
    out.hit = e.hit;
    // The test ran with t_max = the closest hit so far (accepted or waiting for its cell).
    out.t_max = r.ray.t_max;
    for (size_t i = 0; i < index; ++i) {
        const TraversalEvent& p = r.events[i];
        if ((p.kind == EventKind::NewClosest || p.kind == EventKind::HitOutsideCell) && p.t < out.t_max)
            out.t_max = p.t;
    }
    const bool inside = e.u >= 0.0f && e.v >= 0.0f && e.u + e.v <= 1.0f;
    if (e.hit)
        out.verdict = "hit: u, v, 1-u-v >= 0 and t in range";
    else if (std::isinf(e.t) && e.u == 0.0f && e.v == 0.0f)
        out.verdict = "miss: the ray is parallel to the triangle's plane (det = 0, or too small to trust even in double)";
    else if (std::isnan(e.u) || std::isnan(e.v) || std::isnan(e.t))
        out.verdict = "miss: degenerate triangle (no area)";
    else if (e.u < 0.0f)
        out.verdict = "miss: u < 0, outside the triangle";
    else if (e.v < 0.0f)
        out.verdict = "miss: v < 0, outside the triangle";
    else if (!inside)
        out.verdict = "miss: 1-u-v < 0, outside the triangle";
    else if (e.t >= r.ray.t_min && e.t <= out.t_max)
        out.verdict = "miss: u, v say inside, but the ray misses the triangle's own box: rounding on a sliver, "
                      "not a hit (core/geometry/triangle.h)";
    else if (e.t < r.ray.t_min)
        out.verdict = "miss: inside, but behind the ray's start (t < t_min)";
    else if (out.t_max < r.ray.t_max)
        out.verdict = format("miss: inside, but beyond the closest hit so far (t > %.4g)", out.t_max);
    else
        out.verdict = "miss: inside, but beyond the ray's end";
    return out;
}

// [SECTION] Debug geometry

float ray_draw_length(const SteppedRay& r, const Mesh& mesh) {
    const RayPrecomp pre(r.ray);
    const SlabResult scene = slab_test(mesh.bounds(), pre, r.ray.t_min, r.ray.t_max);
    float length = scene.hit() && std::isfinite(scene.t_exit) ? scene.t_exit : 0.0f;
    if (r.hit.found() && std::isfinite(r.hit.t)) length = std::max(length, r.hit.t * 1.05f);
    if (!(length > 0.0f)) {
        const Vec3 e = mesh.bounds().extent();
        length = mesh.bounds().empty() ? 1.0f : std::max({e.x, e.y, e.z, 1e-6f}) * 2.0f;
    }
    return length;
}

namespace {

/// Where the event's interval is, if it has one.
bool has_interval(const TraversalEvent& e) {
    switch (e.kind) {
        case EventKind::BoxTest:
        case EventKind::VisitNode:
        case EventKind::Push:
        case EventKind::Pop:
        case EventKind::Cull:
        case EventKind::EnterCell:
        case EventKind::Leaf: return true;
        default: return false;
    }
}

}  // namespace

void add_cross(DebugGeometry& g, Vec3 p, float size, DebugColour c) {
    for (int a = 0; a < 3; ++a) {
        Vec3 d(0, 0, 0);
        d[a] = size;
        g.segments.push_back({p - d, p + d, c});
    }
}

void add_tested_triangles(DebugGeometry& g, const StepState& s, const Mesh& mesh, size_t max_triangles) {
    const size_t first = s.tested.size() > max_triangles ? s.tested.size() - max_triangles : 0;
    for (size_t i = first; i < s.tested.size(); ++i) {
        const StepState::TestedTriangle& x = s.tested[i];
        if (x.tri >= mesh.triangle_count()) continue;
        g.triangles.push_back({{mesh.vertex(x.tri, 0), mesh.vertex(x.tri, 1), mesh.vertex(x.tri, 2)},
                               x.hit ? kStepColours.triangle_hit : kStepColours.triangle_miss});
    }
}

SiblingTests sibling_box_tests(const std::vector<TraversalEvent>& events, size_t index) {
    if (index >= events.size() || events[index].kind != EventKind::BoxTest) return {index, index};
    SiblingTests run{index, index + 1};
    while (run.first > 0 && events[run.first - 1].kind == EventKind::BoxTest) --run.first;
    while (run.last < events.size() && events[run.last].kind == EventKind::BoxTest) ++run.last;
    return run;
}

DebugGeometry step_geometry(const SteppedRay& r, const StepState& s, const NodeBoxes& boxes, const Mesh& mesh,
                            size_t max_triangles) {
    DebugGeometry g;
    const StepColours& c = kStepColours;
    const float length = ray_draw_length(r, mesh);
    auto at = [&](float t) { return r.ray.origin + r.ray.dir * t; };
    auto clamp_t = [&](float t) { return std::clamp(std::isnan(t) ? 0.0f : t, std::max(r.ray.t_min, 0.0f), length); };
    Aabb scene = mesh.bounds();
    if (auto root = boxes.root()) scene.grow(*root);
    const Vec3 ext = scene.empty() ? Vec3(1, 1, 1) : scene.extent();
    const float mark = 0.02f * std::max({ext.x, ext.y, ext.z, 1e-6f});

    // The ray, and the interval of the current step emphasised.
    g.segments.push_back({at(std::max(r.ray.t_min, 0.0f)), at(length), c.ray});
    const TraversalEvent* interval = nullptr;
    if (s.current && has_interval(*s.current) && !(s.current->kind == EventKind::Leaf && s.current->t_enter == 0.0f &&
                                                   s.current->t_exit == 0.0f))
        interval = &*s.current;
    else if (s.last_visit)
        interval = &*s.last_visit;
    if (interval && interval->t_enter <= interval->t_exit) {
        const float t0 = clamp_t(interval->t_enter), t1 = clamp_t(interval->t_exit);
        g.segments.push_back({at(t0), at(t1), c.interval});
        add_cross(g, at(t0), 0.4f * mark, c.interval);
        add_cross(g, at(t1), 0.4f * mark, c.interval);
    }

    // Boxes: visited (faint), culled, stacked, the current node, the box under test.
    const size_t kMaxVisited = 4000;
    const size_t first_visited = s.visited.size() > kMaxVisited ? s.visited.size() - kMaxVisited : 0;
    if (boxes.is_grid()) {
        for (size_t i = s.cells.size() > kMaxVisited ? s.cells.size() - kMaxVisited : 0; i < s.cells.size(); ++i)
            if (auto b = boxes.of(s.cells[i])) g.boxes.push_back({*b, c.visited});
    } else {
        for (size_t i = first_visited; i < s.visited.size(); ++i)
            if (auto b = boxes.node(s.visited[i])) g.boxes.push_back({*b, c.visited});
    }
    for (const StepState::Culled& x : s.culled) {
        std::optional<Aabb> b = boxes.node(x.node);
        if (!b) continue;
        g.boxes.push_back({*b, x.reason == CullReason::BeyondClosestHit ? c.culled_beyond : c.culled_missed});
    }
    for (size_t i = 0; i < s.stack.size(); ++i) {
        const StepState::StackEntry& x = s.stack[i];
        std::optional<Aabb> b = boxes.node(x.node);
        if (!b) continue;
        g.boxes.push_back({*b, c.stacked});
        const Vec3 where = std::isfinite(x.t_enter) ? at(clamp_t(x.t_enter)) : b->center();
        g.labels.push_back({where, format("stack %zu: node %u, t=%.4g", s.stack.size() - i, x.node, x.t_enter),
                            c.stacked});
    }
    if (s.last_visit)
        if (auto b = boxes.of(*s.last_visit)) g.boxes.push_back({*b, c.current});
    // The box under test, with the boxes tested together with it (a wide node's children).
    if (s.current && s.current->kind == EventKind::BoxTest && s.steps > 0) {
        const SiblingTests run = sibling_box_tests(r.events, std::min(s.steps, r.events.size()) - 1);
        for (size_t i = run.first; i < run.last; ++i)
            if (auto b = boxes.of(r.events[i])) g.boxes.push_back({*b, r.events[i].hit ? c.tested_hit : c.tested_miss});
    }

    // The split plane of the current node (KD tree, octree), clipped to the node's box.
    if (s.current && s.current->kind == EventKind::SplitPlane && s.current->axis == kGeneralPlane) {
        // A BSP node's plane: the polygon it makes inside the node's cell, as a fan.
        const TraversalEvent& e = *s.current;
        const std::vector<Vec3>& poly = boxes.split_polygon(e.node);
        for (size_t i = 1; i + 1 < poly.size(); ++i) {
            DebugQuad q;
            q.corners[0] = poly[0];
            q.corners[1] = poly[i];
            q.corners[2] = q.corners[3] = poly[i + 1];
            q.colour = c.split;
            g.quads.push_back(q);
        }
        if (std::isfinite(e.t)) {
            add_cross(g, at(e.t), 0.5f * mark, c.split);
            g.labels.push_back({at(e.t), format("t_split=%.3g", e.t), DebugColour{80, 220, 230, 255}});
        }
    } else if (s.current && s.current->kind == EventKind::SplitPlane) {
        const TraversalEvent& e = *s.current;
        if (auto b = boxes.node(e.node)) {
            DebugQuad q;
            const std::array<Vec3, 4> corners = plane_across_box(*b, e.axis, e.split);
            std::copy(corners.begin(), corners.end(), q.corners);
            q.colour = c.split;
            g.quads.push_back(q);
            if (std::isfinite(e.t)) {
                add_cross(g, at(e.t), 0.5f * mark, c.split);
                g.labels.push_back({at(e.t), format("t_split=%.3g", e.t), DebugColour{80, 220, 230, 255}});
            }
        }
    }

    add_tested_triangles(g, s, mesh, max_triangles);

    // Hits: waiting for their cell, and the closest so far.
    for (const TraversalEvent& e : s.rejected) {
        if (s.closest.found() && s.closest.tri == e.tri && s.closest.t == e.t) continue;  // accepted since
        add_cross(g, at(e.t), mark, c.rejected);
        g.labels.push_back({at(e.t), format("outside cell: t=%.5g > %.5g", e.t, e.t_exit), c.rejected});
    }
    if (s.closest.found() && std::isfinite(s.closest.t)) {
        add_cross(g, at(s.closest.t), mark, c.closest);
        g.labels.push_back({at(s.closest.t), format("closest t=%.4g", s.closest.t), c.closest});
    }
    return g;
}

// [SECTION] Compare table

Expected<CompareSet> build_compare_set(const Mesh& mesh) {
    CompareSet set;
    auto add = [&](const std::string& label, AccelConfig config) -> std::optional<Error> {
        auto accel = build_accelerator(mesh, config);
        if (!accel) return Error{label + ": " + accel.error()};
        set.entries.push_back({label, *accel});
        return std::nullopt;
    };
    AccelConfig naive;
    if (auto err = add("naive", naive)) return *err;
    AccelConfig bvh;
    bvh.type = AccelType::Bvh;
    bvh.bvh_traversal = BvhTraversal::Unordered;
    auto bvh_accel = build_accelerator(mesh, bvh);
    if (!bvh_accel) return Error{"bvh: " + bvh_accel.error()};
    set.entries.push_back({"BVH alg. 1 (unordered)", *bvh_accel});
    // One build, the other traversal: a copy of the same tree.
    if (const Bvh* built = structure_if<Bvh>(**bvh_accel)) {
        Bvh ordered = *built;
        ordered.traversal = BvhTraversal::Ordered;
        set.entries.push_back(
            {"BVH alg. 2 (ordered)", std::make_shared<AcceleratorFor<Bvh>>(std::move(ordered))});
    }
    for (const AccelType type : {AccelType::Grid, AccelType::Kd, AccelType::Octree}) {
        AccelConfig config;
        config.type = type;
        const std::string label = type == AccelType::Kd ? "KD tree" : std::string(to_string(type));
        if (auto err = add(label, config)) return *err;
    }
    return set;
}

std::vector<CompareRow> compare_ray(const CompareSet& set, const Ray& ray, StopAt query) {
    std::vector<CompareRow> rows;
    for (const CompareSet::Entry& entry : set.entries) {
        CountingObserver counter;
        CompareRow row;
        row.label = entry.label;
        if (query == StopAt::AnyHit)
            row.blocked = entry.accel->intersect_any(ray, counter);
        else
            row.hit = entry.accel->intersect_closest(ray, counter);
        row.counters = counter.counters;
        if (!rows.empty())
            row.agrees_with_naive = query == StopAt::AnyHit
                                        ? row.blocked == rows.front().blocked
                                        : row.hit.tri == rows.front().hit.tri &&
                                              (row.hit.t == rows.front().hit.t || !row.hit.found());
        rows.push_back(std::move(row));
    }
    return rows;
}

}  // namespace accelviz
