#include "core/stepper/nearest_stepper.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/traversal/observers.h"

namespace accelviz {

namespace {

std::string format(const char* fmt, auto... args) {
    char text[320];
    std::snprintf(text, sizeof text, fmt, args...);
    return text;
}

/// "the best distance 0.25", or that there is none yet.
std::string best_so_far(const StepState& s) {
    return s.closest.found() ? format("the best distance %.4g", s.closest.t) : std::string("no best distance yet");
}

/// The point of `box` nearest to q (q itself inside it).
Vec3 nearest_on_box(Vec3d q, const Aabb& box) {
    return {float(std::clamp(q.x, double(box.lo.x), double(box.hi.x))),
            float(std::clamp(q.y, double(box.lo.y), double(box.hi.y))),
            float(std::clamp(q.z, double(box.lo.z), double(box.hi.z)))};
}

/// A circle of radius r around c in the plane spanned by unit vectors a and b.
void add_circle(DebugGeometry& g, Vec3d c, double r, Vec3d a, Vec3d b, DebugColour colour) {
    constexpr int kSegments = 72;
    auto at = [&](int k) {
        const double angle = 2.0 * std::numbers::pi * k / kSegments;
        return to_float(c + a * (r * std::cos(angle)) + b * (r * std::sin(angle)));
    };
    for (int k = 0; k < kSegments; ++k) g.segments.push_back({at(k), at(k + 1), colour});
}

}  // namespace

Expected<SteppedNearest> record_nearest(const Accelerator& accel, const Mesh& mesh, Vec3d query) {
    if (!has_nearest_search(accel))
        return Error{"the nearest-point search walks naive, the binary BVH or the KD tree; the " + accel.name() +
                     " answers rays only"};
    SteppedNearest out;
    out.query = query;
    out.structure = accel.name();
    RecordingObserver recorder;
    out.result = nearest_point(accel, mesh, query, recorder);
    out.events = std::move(recorder.events);
    return out;
}

Vec3d default_query_point(const Aabb& bounds) {
    if (bounds.empty()) return {0, 0, 0};
    const Vec3d c = to_double(bounds.center()), e = to_double(bounds.extent());
    const double size = std::max({e.x, e.y, e.z, 1e-6});
    return {c.x + 0.3 * e.x, c.y + 0.2 * e.y, c.z + 0.5 * e.z + 0.1 * size};
}

std::string explain_nearest_event(const TraversalEvent& e, const StepState& after) {
    switch (e.kind) {
        case EventKind::Push: return format("node %u waits on the stack: its box is %.4g from q", e.node, e.t_enter);
        case EventKind::Pop: return format("take node %u off the stack (its box is %.4g from q)", e.node, e.t_enter);
        case EventKind::VisitNode:
            return format("visit node %u: its box is %.4g from q, not beyond %s", e.node, e.t_enter,
                          best_so_far(after).c_str());
        case EventKind::Cull:
            return format("skip node %u and all below it: its box is %.4g from q, beyond %s (wholly outside the "
                          "sphere)",
                          e.node, e.t_enter, best_so_far(after).c_str());
        case EventKind::Leaf: return format("leaf node %u: measure its %u triangles", e.node, e.count);
        case EventKind::TriangleTest:
            if (e.hit) return format("triangle %u is %.4g from q: the nearest so far", e.tri, e.t);
            return format("triangle %u is %.4g from q: not nearer than %s", e.tri, e.t, best_so_far(after).c_str());
        case EventKind::NewClosest:
            return format("the best distance shrinks to %.4g (triangle %u): the sphere shrinks, boxes outside it "
                          "will be skipped",
                          e.t, e.tri);
        case EventKind::Done:
            if (!e.hit) return "done: no triangles, no nearest point";
            return format("done: the nearest point is on triangle %u, %.4g from q", e.tri, e.t);
        default: return std::string(to_string(e.kind));
    }
}

std::string describe_nearest_event(const TraversalEvent& e) {
    switch (e.kind) {
        case EventKind::Push: return format("push node %u  d=%.4g", e.node, e.t_enter);
        case EventKind::Pop: return format("pop node %u  d=%.4g", e.node, e.t_enter);
        case EventKind::VisitNode: return format("visit node %u  d=%.4g", e.node, e.t_enter);
        case EventKind::Cull: return format("skip node %u  d=%.4g: outside the sphere", e.node, e.t_enter);
        case EventKind::Leaf: return format("leaf node %u: %u triangles", e.node, e.count);
        case EventKind::TriangleTest: return format("triangle %u  d=%.4g%s", e.tri, e.t, e.hit ? ": nearest so far" : "");
        case EventKind::NewClosest: return format("best d=%.4g (triangle %u)", e.t, e.tri);
        case EventKind::Done:
            return e.hit ? format("done: triangle %u  d=%.4g", e.tri, e.t) : std::string("done: no triangles");
        default: return std::string(to_string(e.kind));
    }
}

DebugGeometry nearest_geometry(const SteppedNearest& r, const StepState& s, const NodeBoxes& boxes, const Mesh& mesh,
                               size_t max_triangles) {
    DebugGeometry g;
    const StepColours& c = kStepColours;
    const Vec3d q = r.query;
    Aabb scene = mesh.bounds();
    if (auto root = boxes.root()) scene.grow(*root);
    scene.grow(to_float(q));
    const Vec3 ext = scene.extent();
    const float mark = 0.02f * std::max({ext.x, ext.y, ext.z, 1e-6f});

    // Boxes: visited (faint), skipped (outside the sphere), waiting, the current node.
    constexpr size_t kMaxVisited = 4000;
    for (size_t i = s.visited.size() > kMaxVisited ? s.visited.size() - kMaxVisited : 0; i < s.visited.size(); ++i)
        if (auto b = boxes.node(s.visited[i])) g.boxes.push_back({*b, c.visited});
    for (const StepState::Culled& x : s.culled)
        if (auto b = boxes.node(x.node)) g.boxes.push_back({*b, c.culled_missed});  // pruned: grey
    for (size_t i = 0; i < s.stack.size(); ++i) {
        const StepState::StackEntry& x = s.stack[i];
        std::optional<Aabb> b = boxes.node(x.node);
        if (!b) continue;
        g.boxes.push_back({*b, c.stacked});
        if (i + 1 == s.stack.size())  // the top: taken next
            g.labels.push_back({b->center(), format("next: node %u, d=%.4g", x.node, x.t_enter), c.stacked});
    }
    if (s.last_visit)
        if (auto b = boxes.node(s.last_visit->node)) g.boxes.push_back({*b, c.current});
    // The box whose distance is being compared: a line from q to its nearest point.
    if (s.current && (s.current->kind == EventKind::Cull || s.current->kind == EventKind::VisitNode ||
                      s.current->kind == EventKind::Pop))
        if (auto b = boxes.node(s.current->node)) {
            const bool skipped = s.current->kind == EventKind::Cull;
            g.segments.push_back({to_float(q), nearest_on_box(q, *b), skipped ? c.tested_miss : c.current});
            g.boxes.push_back({*b, skipped ? c.tested_miss : c.current});
        }

    // Triangles measured (the latest max_triangles; green: nearer than all before), and
    // the current one's nearest point.
    add_tested_triangles(g, s, mesh, max_triangles);
    if (s.current && s.current->kind == EventKind::TriangleTest && s.current->tri < mesh.triangle_count()) {
        const NearestPoint m = measure_triangle(mesh, s.current->tri, q);
        const DebugColour colour = s.current->hit ? c.tested_hit : c.tested_miss;
        g.segments.push_back({to_float(q), to_float(m.point), colour});
        add_cross(g, to_float(m.point), 0.4f * mark, colour);
    }

    // The best so far: the sphere of its distance (three great circles) and its point.
    if (s.closest.found() && s.closest.tri < mesh.triangle_count()) {
        const NearestPoint best = measure_triangle(mesh, s.closest.tri, q);
        const double radius = best.distance();
        add_circle(g, q, radius, {1, 0, 0}, {0, 1, 0}, c.closest);
        add_circle(g, q, radius, {0, 1, 0}, {0, 0, 1}, c.closest);
        add_circle(g, q, radius, {0, 0, 1}, {1, 0, 0}, c.closest);
        g.segments.push_back({to_float(q), to_float(best.point), c.closest});
        add_cross(g, to_float(best.point), mark, c.closest);
        g.labels.push_back({to_float(best.point), format("nearest so far: d=%.4g", radius), c.closest});
    }
    add_cross(g, to_float(q), mark, c.query);
    g.labels.push_back({to_float(q), "q", c.query});
    return g;
}

}  // namespace accelviz
