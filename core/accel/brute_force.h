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

    explicit BruteForce(const Mesh& mesh) : triangles(make_triangles(mesh)) {}

    static constexpr AccelType kType = AccelType::Naive;
    std::string name() const { return std::string(to_string(kType)); }
    nlohmann::json config() const { return nlohmann::json::object(); }
    nlohmann::json stats() const { return {{"triangles", triangles.size()}}; }

    template <class Observer>
    Hit intersect_closest(const Ray& ray, Observer& obs) const {
        Hit best;
        Ray r = ray;
        const BoxTestRay box_ray(ray);
        for (uint32_t id = 0; id < triangles.size(); ++id) {
            const TriangleTest test = intersect_triangle(triangles[id], r, box_ray);
            obs.on({.kind = EventKind::TriangleTest, .hit = test.hit, .tri = id,
                    .t = test.t, .u = test.u, .v = test.v});
            if (test.hit && is_closer(test.t, id, best)) {
                best = {id, test.t, test.u, test.v};
                r.t_max = test.t;  // later triangles must be at least this close
                obs.on({.kind = EventKind::NewClosest, .tri = id, .t = test.t, .u = test.u, .v = test.v});
            }
        }
        obs.on({.kind = EventKind::Done, .hit = best.found(), .tri = best.tri, .t = best.t,
                .u = best.u, .v = best.v});
        return best;
    }

    bool intersect_any(const Ray& ray) const {
        const BoxTestRay box_ray(ray);
        for (const Triangle& tri : triangles)
            if (intersect_triangle(tri, ray, box_ray).hit) return true;
        return false;
    }
};

}  // namespace accelviz
