#pragma once
/// The O(N) baseline of the lecture (光线与网格相交 — 最简单的算法): test the ray
/// against every triangle and keep the closest. It is the oracle every
/// acceleration structure is tested against.

#include <vector>

#include <nlohmann/json.hpp>

#include "core/accel/accel_type.h"
#include "core/geometry/mesh.h"
#include "core/traversal/observers.h"

namespace accelviz {

struct BruteForce {
    TriangleArray triangles;  ///< indexed by triangle id
    CornerArray corners;      ///< the same, as corners; only for the watertight test
    TriangleTestKind triangle_test = TriangleTestKind::MollerTrumbore;

    explicit BruteForce(const Mesh& mesh, TriangleTestKind test = TriangleTestKind::MollerTrumbore)
        : triangles(make_triangles(mesh)), triangle_test(test) {
        if (test == TriangleTestKind::Watertight) corners = make_corners(mesh);
    }

    static constexpr AccelType kType = AccelType::Naive;
    std::string name() const { return std::string(to_string(kType)); }
    nlohmann::json config() const { return {{"triangle_test", to_string(triangle_test)}}; }
    nlohmann::json stats() const { return {{"triangles", triangles.size()}}; }

    template <class Observer>
    Hit intersect_closest(const Ray& ray, Observer& obs) const {
        return triangle_test == TriangleTestKind::Watertight ? closest<TriangleTestKind::Watertight>(ray, obs)
                                                             : closest<TriangleTestKind::MollerTrumbore>(ray, obs);
    }

    /// Any hit in [t_min, t_max] (shadow rays): the first triangle, by id, that is hit.
    template <class Observer>
    bool intersect_any(const Ray& ray, Observer& obs) const {
        return triangle_test == TriangleTestKind::Watertight ? any<TriangleTestKind::Watertight>(ray, obs)
                                                             : any<TriangleTestKind::MollerTrumbore>(ray, obs);
    }
    bool intersect_any(const Ray& ray) const {
        NoObserver none;
        return intersect_any(ray, none);
    }

private:
    template <TriangleTestKind kTest, class Observer>
    Hit closest(const Ray& ray, Observer& obs) const {
        Hit best;
        Ray r = ray;
        const TriangleTester<kTest> tester(ray, triangles, corners);
        for (uint32_t id = 0; id < triangles.size(); ++id) {
            const TriangleTest test = tester.test(id, r);
            obs.on({.kind = EventKind::TriangleTest, .hit = test.hit, .tri = id,
                    .t = test.t, .u = test.u, .v = test.v});
            if (test.hit && is_closer(test.t, id, best)) {
                best = {id, test.t, test.u, test.v};
                r.t_max = test.t;  // later triangles must be at least this close
                obs.on({.kind = EventKind::NewClosest, .tri = id, .t = test.t, .u = test.u, .v = test.v});
            }
        }
        return report_done(best, obs);
    }

    template <TriangleTestKind kTest, class Observer>
    bool any(const Ray& ray, Observer& obs) const {
        const TriangleTester<kTest> tester(ray, triangles, corners);
        Hit found;
        for (uint32_t id = 0; id < triangles.size() && !found.found(); ++id) {
            const TriangleTest test = tester.test(id, ray);
            obs.on({.kind = EventKind::TriangleTest, .hit = test.hit, .tri = id, .t = test.t, .u = test.u,
                    .v = test.v});
            if (test.hit) found = {id, test.t, test.u, test.v};
        }
        return report_done(found, obs).found();
    }
};

}  // namespace accelviz
