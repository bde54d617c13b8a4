// `accelviz query SCENE --nearest X,Y,Z [--accel naive|bvh|kd] [--json]`: the point
// on the mesh nearest to a point, through the chosen structure, with every event of
// the search and its counters (core/query/nearest_point.h), like `trace` for a ray.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/cli/accel_flags.h"
#include "app/cli/commands.h"
#include "app/cli/progress.h"
#include "app/cli/scene_input.h"
#include "core/query/inside.h"
#include "core/query/nearest_point.h"
#include "core/render/camera.h"
#include "core/traversal/event_json.h"
#include "core/traversal/observers.h"
#include "core/util/random.h"

namespace accelviz::cli {
namespace {

struct QueryOptions {
    std::string scene;
    std::string nearest;
    std::string inside;
    int random = 0;  ///< instead of --nearest: this many seeded points, averaged
    uint64_t seed = 1;
    bool json = false;
    AccelConfig accel;
};

/// --random N: seeded points uniform in the scene's box grown to twice its size; the
/// work per query (counted) and the time per query (the fast path, one thread).
int run_random_queries(const QueryOptions& opt, const Mesh& mesh, const Accelerator& accel) {
    Rng rng(opt.seed);
    const Aabb box = mesh.bounds();
    const Vec3 c = box.center(), e = box.extent();
    std::vector<Vec3d> points;
    for (int i = 0; i < opt.random; ++i)
        points.push_back({c.x + e.x * rng.uniform(-1.0f, 1.0f), c.y + e.y * rng.uniform(-1.0f, 1.0f),
                          c.z + e.z * rng.uniform(-1.0f, 1.0f)});
    Counters counters;
    for (const Vec3d& q : points) {
        CountingObserver counter;
        nearest_point(accel, mesh, q, counter);
        counters += counter.counters;
    }
    double checksum = 0;
    const auto start = std::chrono::steady_clock::now();
    for (const Vec3d& q : points) {
        NoObserver none;
        checksum += nearest_point(accel, mesh, q, none).distance_squared;
    }
    const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count() /
                      double(points.size());
    const double n = double(points.size());
    if (opt.json) {
        nlohmann::ordered_json out;
        out["scene"] = opt.scene;
        out["triangles"] = mesh.triangle_count();
        out["accel"] = accel.name();
        out["config"] = accel.config();
        out["queries"] = points.size();
        out["seed"] = opt.seed;
        out["nodes_per_query"] = double(counters.nodes_visited) / n;
        out["triangles_per_query"] = double(counters.triangle_tests) / n;
        out["us_per_query"] = us;
        out["checksum"] = checksum;
        std::cout << out.dump(1) << "\n";
        return 0;
    }
    std::printf("%s, %zu triangles, %s: %zu seeded points (seed %llu) in twice the scene's box\n", opt.scene.c_str(),
                mesh.triangle_count(), accel.name().c_str(), points.size(), (unsigned long long)opt.seed);
    std::printf("per query: %.1f nodes visited, %.1f triangles measured, %.2f us (one thread)\n",
                double(counters.nodes_visited) / n, double(counters.triangle_tests) / n, us);
    return 0;
}

/// --inside: the three voting rays' crossings, counted through the BVH or brute force.
int run_inside(const QueryOptions& opt, const Mesh& mesh, const Accelerator& accel, Vec3d point) {
    const Vec3 q = to_float(point);
    const Bvh* bvh = structure_if<Bvh>(accel);
    const TriangleArray triangles = bvh ? TriangleArray{} : make_triangles(mesh);
    Counters counters;
    std::vector<std::vector<TraversalEvent>> events;  // per ray, for --json (a stepper's replay)
    const InsideTest result = inside_by_parity(q, [&](const Ray& ray) {
        RecordingObserver recorder;
        const uint32_t n =
            bvh ? count_crossings(*bvh, ray, recorder) : count_crossings_brute_force(triangles, ray, recorder);
        counters += recorder.counters();
        events.push_back(std::move(recorder.events));
        return n;
    });
    const auto directions = parity_directions();
    if (opt.json) {
        nlohmann::ordered_json out;
        out["scene"] = opt.scene;
        out["triangles"] = mesh.triangle_count();
        out["accel"] = accel.name();
        out["query"] = {{"inside", {q.x, q.y, q.z}}};
        nlohmann::json rays = nlohmann::json::array();
        for (size_t i = 0; i < 3; ++i)
            rays.push_back({{"dir", {directions[i].x, directions[i].y, directions[i].z}},
                            {"crossings", result.crossings[i]},
                            {"events", to_json(events[i])}});
        out["rays"] = rays;
        out["votes_inside"] = result.votes_inside;
        out["inside"] = result.inside;
        out["counters"] = to_json(counters);
        std::cout << out.dump(1) << "\n";
        return 0;
    }
    std::printf("%s, %zu triangles, %s\n", opt.scene.c_str(), mesh.triangle_count(), accel.name().c_str());
    for (size_t i = 0; i < 3; ++i)
        std::printf("ray along (%.4f, %.4f, %.4f): %u crossings (%s)\n", directions[i].x, directions[i].y,
                    directions[i].z, result.crossings[i], result.crossings[i] % 2 ? "odd: inside" : "even: outside");
    std::printf("(%.9g, %.9g, %.9g) is %s (%d of 3 rays say inside)\n", q.x, q.y, q.z,
                result.inside ? "inside" : "outside", result.votes_inside);
    std::printf("work: %llu nodes visited, %llu triangles tested\n", (unsigned long long)counters.nodes_visited,
                (unsigned long long)counters.triangle_tests);
    return 0;
}

int run_query(const QueryOptions& opt) {
    auto fail = [](const std::string& message) {
        std::cerr << "accelviz query: " << message << "\n";
        return 1;
    };
    const int asked = (opt.nearest.empty() ? 0 : 1) + (opt.inside.empty() ? 0 : 1) + (opt.random > 0 ? 1 : 0);
    if (asked != 1) return fail("give one of --nearest X,Y,Z, --inside X,Y,Z and --random N");
    const std::string& text = !opt.nearest.empty() ? opt.nearest : opt.inside;
    auto point = text.empty() ? Expected<Vec3d>(Vec3d{}) : parse_vec3(text);
    const std::string flag = opt.nearest.empty() ? "--inside: " : "--nearest: ";
    if (!point) return fail(flag + point.error());
    for (double c : {point->x, point->y, point->z})
        if (!(std::abs(c) <= kMaxCoordinate))
            return fail(flag + "each coordinate must be within +-" + std::to_string(int64_t(kMaxCoordinate)) +
                        " (the meshes' own limit)");
    const AccelType type = opt.accel.type;
    if (!opt.inside.empty() && type != AccelType::Naive && type != AccelType::Bvh)
        return fail("--inside counts crossings through naive or bvh: use --accel naive or bvh");
    if (type != AccelType::Naive && type != AccelType::Bvh && type != AccelType::Kd)
        return fail("--nearest goes through naive, bvh or kd (the " + std::string(to_string(type)) +
                    " answers rays only): use --accel naive, bvh or kd");
    if (type == AccelType::Bvh && opt.accel.bvh.width != 2)
        return fail("the nearest-point and inside queries walk the binary BVH: --bvh-width " +
                    std::to_string(opt.accel.bvh.width) + " is for rays (render, trace, bench)");
    auto mesh = load_scene_noting(opt.scene, "query");
    if (!mesh) return fail(mesh.error());
    auto accel = [&] {
        const StepProgress progress("query", "building " + std::string(to_string(type)));
        return build_accelerator(*mesh, opt.accel);
    }();
    if (!accel) return fail(accel.error());
    print_memory_budget_note(**accel, "query");
    if (opt.random > 0) return run_random_queries(opt, *mesh, **accel);
    if (!opt.inside.empty()) return run_inside(opt, *mesh, **accel, *point);

    const Vec3d q = *point;
    RecordingObserver recorder;
    const NearestPoint nearest = nearest_point(**accel, *mesh, q, recorder);
    const Counters counters = recorder.counters();
    uint64_t culled = 0;
    for (const TraversalEvent& e : recorder.events) culled += e.kind == EventKind::Cull ? 1 : 0;

    if (opt.json) {
        nlohmann::ordered_json out;
        out["scene"] = opt.scene;
        out["triangles"] = mesh->triangle_count();
        out["accel"] = (*accel)->name();
        out["config"] = (*accel)->config();
        out["query"] = {{"nearest", {q.x, q.y, q.z}}};
        out["events"] = to_json(recorder.events);
        if (nearest.found())
            out["result"] = {{"triangle", nearest.tri},
                             {"distance", nearest.distance()},
                             {"point", {nearest.point.x, nearest.point.y, nearest.point.z}}};
        else
            out["result"] = nullptr;
        out["counters"] = to_json(counters);
        std::cout << out.dump(1) << "\n";
        return 0;
    }
    std::printf("%s, %zu triangles, %s %s\n", opt.scene.c_str(), mesh->triangle_count(), (*accel)->name().c_str(),
                (*accel)->config().dump().c_str());
    for (size_t i = 0; i < recorder.events.size(); ++i)
        std::printf("%6zu  %s\n", i, describe(recorder.events[i]).c_str());
    if (nearest.found())
        std::printf("nearest to (%.9g, %.9g, %.9g): triangle %u at distance %.9g, point (%.9g, %.9g, %.9g)\n", q.x,
                    q.y, q.z, nearest.tri, nearest.distance(), nearest.point.x, nearest.point.y, nearest.point.z);
    else
        std::printf("no triangles: no nearest point\n");
    std::printf("work: %llu nodes visited, %llu skipped as farther than the best, %llu triangles measured (of %zu)\n",
                (unsigned long long)counters.nodes_visited, (unsigned long long)culled,
                (unsigned long long)counters.triangle_tests, mesh->triangle_count());
    return 0;
}

}  // namespace

Command register_query(CLI::App& app) {
    auto opt = std::make_shared<QueryOptions>();
    CLI::App* sub = app.add_subcommand(
        "query", "The point on the mesh nearest to a point (--nearest X,Y,Z), through naive, the BVH or the KD tree, "
                 "with every event of the search; or the average work and time over --random N points; or whether a point "
                 "is inside a closed mesh (--inside X,Y,Z, by ray parity)");
    sub->add_option("scene", opt->scene, "OBJ file, or builtin:NAME (e.g. builtin:teapot)")->required();
    sub->add_option("--nearest", opt->nearest, "The query point X,Y,Z");
    sub->add_option("--inside", opt->inside,
                    "Is X,Y,Z inside the (closed) mesh? Three rays from it count their crossings (odd: "
                    "inside) and vote");
    sub->add_option("--random", opt->random,
                    "Instead of --nearest: N seeded points in twice the scene's box; prints the nodes visited, "
                    "triangles measured and microseconds per query (one thread)")
        ->check(CLI::Range(1, 10000000));
    sub->add_option("--seed", opt->seed, "--random: the points' seed")->capture_default_str();
    sub->add_flag("--json", opt->json, "One JSON object: query, events (array), result, counters");
    add_accel_flags(*sub, opt->accel);
    return {sub, [opt] { return run_query(*opt); }};
}

}  // namespace accelviz::cli
