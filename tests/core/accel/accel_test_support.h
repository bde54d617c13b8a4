#pragma once
/// What every acceleration-structure test needs: seeded random rays of the kinds
/// that break structures (origins inside and outside, axis-aligned directions,
/// ±0 components, origins on box planes, rays starting inside boxes, rays through
/// vertices, finite ranges), and the brute-force answers for them, computed once.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>

#include "core/accel/brute_force.h"
#include "core/accel/factory.h"
#include "core/geometry/mesh.h"
#include "core/util/random.h"

namespace accelviz::test {

/// How many of `n` seeded rays an exactness test traces in this build: all of them,
/// or a quarter in a sanitized build (scripts/test --sanitize), which runs every
/// code path the plain build does several times slower; a memory error shows on the
/// first rays that take its path, and the plain build checks every ray's answer.
constexpr size_t rays_for_this_build(size_t n) {
#ifdef ACCELVIZ_SANITIZED
    return n / 4;
#else
    return n;
#endif
}

/// Every structure with every option that changes what it builds or how it walks
/// (builders, the BVH's two traversals, grid insertion, KD and octree clipping,
/// mailbox on and off), each with a label: what exactness and determinism are
/// tested on, and what the fuzzer checks against brute force.
inline std::vector<std::pair<std::string, AccelConfig>> all_configurations() {
    std::vector<std::pair<std::string, AccelConfig>> out;
    for (BvhBuilder builder : {BvhBuilder::Midpoint, BvhBuilder::Median, BvhBuilder::SahSweep, BvhBuilder::SahBinned}) {
        AccelConfig c;
        c.type = AccelType::Bvh;
        c.bvh.builder = builder;
        out.push_back({"bvh " + std::string(to_string(builder)), c});
    }
    AccelConfig unordered;
    unordered.type = AccelType::Bvh;
    unordered.bvh_traversal = BvhTraversal::Unordered;
    out.push_back({"bvh unordered", unordered});
    for (int width : {4, 8}) {
        AccelConfig wide;
        wide.type = AccelType::Bvh;
        wide.bvh.width = width;
        out.push_back({"bvh width " + std::to_string(width), wide});
    }
    for (GridInsert insert : {GridInsert::Box, GridInsert::Exact})
        for (bool mailbox : {true, false}) {
            AccelConfig c;
            c.type = AccelType::Grid;
            c.grid.insert = insert;
            c.grid.mailbox = mailbox;
            out.push_back({"grid " + std::string(to_string(insert)) + (mailbox ? "" : " no-mailbox"), c});
        }
    for (KdBuilder builder : {KdBuilder::Median, KdBuilder::Sah})
        for (ClipMode clip : {ClipMode::Box, ClipMode::Exact}) {
            AccelConfig c;
            c.type = AccelType::Kd;
            c.kd.builder = builder;
            c.kd.clip = clip;
            c.kd.mailbox = clip == ClipMode::Box;  // both mailbox states, without doubling the list
            out.push_back({"kd " + std::string(to_string(builder)) + " " + std::string(to_string(clip)) +
                               (c.kd.mailbox ? " mailbox" : ""),
                           c});
        }
    for (ClipMode clip : {ClipMode::Box, ClipMode::Exact}) {
        AccelConfig c;
        c.type = AccelType::Octree;
        c.octree.clip = clip;
        c.octree.mailbox = clip == ClipMode::Box;
        out.push_back({"octree " + std::string(to_string(clip)) + (c.octree.mailbox ? "" : " no-mailbox"), c});
    }
    for (bool mailbox : {true, false}) {
        AccelConfig c;
        c.type = AccelType::Bsp;
        c.bsp.mailbox = mailbox;
        c.bsp.candidates = mailbox ? 24 : 3;  // fewer planes tried: more axis-aligned fallbacks
        out.push_back({std::string("bsp") + (mailbox ? "" : " no-mailbox few-candidates"), c});
    }
    // The watertight triangle test, once per structure (the test is the same code in
    // every structure; what differs is how each walks to it).
    for (AccelType type : {AccelType::Bvh, AccelType::Grid, AccelType::Kd, AccelType::Octree, AccelType::Bsp}) {
        AccelConfig c;
        c.type = type;
        c.triangle_test = TriangleTestKind::Watertight;
        out.push_back({std::string(to_string(type)) + " watertight", c});
    }
    return out;
}

/// A direction uniform on the unit sphere.
inline Vec3 random_direction(Rng& rng) {
    while (true) {
        const Vec3 d{rng.uniform(-1.0f, 1.0f), rng.uniform(-1.0f, 1.0f), rng.uniform(-1.0f, 1.0f)};
        const float len2 = dot(d, d);
        if (len2 > 1e-4f && len2 <= 1.0f) return d / std::sqrt(len2);
    }
}

inline Vec3 random_point_in(Rng& rng, const Aabb& box) {
    return {rng.uniform(box.lo.x, box.hi.x), rng.uniform(box.lo.y, box.hi.y), rng.uniform(box.lo.z, box.hi.z)};
}

/// +0 or -0, at random: both must behave alike.
inline float signed_zero(Rng& rng) { return rng.below(2) ? 0.0f : -0.0f; }

/// `count` seeded rays over `mesh`. Ten kinds in turn (see the comments below).
inline std::vector<Ray> make_test_rays(const Mesh& mesh, size_t count, uint64_t seed) {
    Rng rng(seed);
    Aabb bounds = mesh.bounds();
    if (bounds.empty()) bounds = {{-1, -1, -1}, {1, 1, 1}};
    const Vec3 centre = bounds.center();
    const float diagonal = std::max(length(bounds.extent()), 1e-3f);
    const Vec3 margin = Vec3{1, 1, 1} * (0.25f * diagonal);
    const Aabb around{bounds.lo - margin, bounds.hi + margin};
    const size_t tris = mesh.triangle_count();

    std::vector<Ray> rays;
    rays.reserve(count);
    for (size_t i = 0; i < count; ++i) {
        Ray ray;
        switch (i % 10) {
            case 0:  // from outside, aimed at a point inside the bounds
                ray.origin = centre + random_direction(rng) * (1.5f * diagonal);
                ray.dir = normalize(random_point_in(rng, bounds) - ray.origin);
                break;
            case 1:  // from inside the bounds, any direction
                ray.origin = random_point_in(rng, bounds);
                ray.dir = random_direction(rng);
                break;
            case 2: {  // axis-aligned: one component ±1, the others ±0
                const int axis = int(rng.below(3));
                ray.origin = random_point_in(rng, around);
                ray.dir = {signed_zero(rng), signed_zero(rng), signed_zero(rng)};
                ray.dir[axis] = rng.below(2) ? 1.0f : -1.0f;
                break;
            }
            case 3: {  // one component ±0
                ray.origin = random_point_in(rng, around);
                ray.dir = random_direction(rng);
                ray.dir[int(rng.below(3))] = signed_zero(rng);
                break;
            }
            case 4: {  // origin exactly on a vertex's coordinate plane (a box plane), moving along it
                ray.origin = random_point_in(rng, around);
                ray.dir = random_direction(rng);
                if (tris > 0) {
                    const int axis = int(rng.below(3));
                    ray.origin[axis] = mesh.vertex(rng.below(tris), int(rng.below(3)))[axis];
                    ray.dir[axis] = signed_zero(rng);
                }
                break;
            }
            case 5:  // starting inside a triangle's box (so inside every box above it)
                ray.origin = tris > 0 ? random_point_in(rng, mesh.triangle_bounds(rng.below(tris)))
                                      : random_point_in(rng, bounds);
                ray.dir = random_direction(rng);
                break;
            case 6:  // starting exactly at a vertex: t = 0 ties between the triangles sharing it
                ray.origin = tris > 0 ? mesh.vertex(rng.below(tris), int(rng.below(3))) : centre;
                ray.dir = random_direction(rng);
                break;
            case 7:  // from outside through a vertex: ties on shared edges and vertices
                ray.origin = centre + random_direction(rng) * (1.5f * diagonal);
                ray.dir = tris > 0 ? mesh.vertex(rng.below(tris), int(rng.below(3))) - ray.origin
                                   : random_direction(rng);
                break;
            case 8:  // a finite segment: t in [t_min, t_max], sometimes reaching behind the origin (t_min < 0)
                ray.origin = random_point_in(rng, around);
                ray.dir = random_direction(rng);
                ray.t_min = rng.uniform(-0.3f * diagonal, 0.3f * diagonal);
                ray.t_max = ray.t_min + rng.uniform(0.0f, diagonal);
                break;
            default:  // from outside, aimed at a triangle's centroid (nearly always a hit)
                ray.origin = centre + random_direction(rng) * (1.5f * diagonal);
                ray.dir = tris > 0 ? normalize(mesh.triangle_bounds(rng.below(tris)).center() - ray.origin)
                                   : random_direction(rng);
                break;
        }
        rays.push_back(ray);
    }
    return rays;
}

/// The watertight test's brute force for every ray (see brute_force_answers): the
/// same layout, each lane computing what intersect_triangle_watertight computes up
/// to its inside test in float; a lane inside, or with an edge function of zero
/// (which the test recomputes in double), is then tested by the test itself.
inline std::vector<Hit> brute_force_answers_watertight(const Mesh& mesh, const std::vector<Ray>& rays) {
    const CornerArray tris = make_corners(mesh);
    const size_t n = tris.size();
    std::vector<float> c[9];  // p0, p1, p2, x y z each
    for (auto& v : c) v.resize(n);
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            const Vec3 p = k == 0 ? tris[i].p0 : k == 1 ? tris[i].p1 : tris[i].p2;
            c[3 * k][i] = p.x; c[3 * k + 1][i] = p.y; c[3 * k + 2][i] = p.z;
        }
    std::vector<Hit> answers(rays.size());
    tbb::parallel_for(size_t(0), rays.size(), [&](size_t r) {
        const Ray& ray = rays[r];
        const WatertightRay sheared(ray);
        const BoxTestRay box_ray(ray);
        const int kx = sheared.kx, ky = sheared.ky, kz = sheared.kz;
        const float* x[3] = {c[kx].data(), c[3 + kx].data(), c[6 + kx].data()};
        const float* y[3] = {c[ky].data(), c[3 + ky].data(), c[6 + ky].data()};
        const float* z[3] = {c[kz].data(), c[3 + kz].data(), c[6 + kz].data()};
        const float ox = ray.origin[kx], oy = ray.origin[ky], oz = ray.origin[kz];
        constexpr size_t kBlock = 512;
        unsigned char candidate[kBlock];
        Hit best;
        for (size_t begin = 0; begin < n; begin += kBlock) {
            const size_t m = std::min(kBlock, n - begin);
            for (size_t k = 0; k < m; ++k) {  // intersect_triangle_watertight, one lane per triangle
                const size_t i = begin + k;
                float sx[3], sy[3];
                for (int j = 0; j < 3; ++j) {
                    const float az = z[j][i] - oz;
                    sx[j] = (x[j][i] - ox) - sheared.shear_x * az;
                    sy[j] = (y[j][i] - oy) - sheared.shear_y * az;
                }
                const float e0 = sx[2] * sy[1] - sy[2] * sx[1];
                const float e1 = sx[0] * sy[2] - sy[0] * sx[2];
                const float e2 = sx[1] * sy[0] - sy[1] * sx[0];
                const bool zero = (e0 == 0.0f) | (e1 == 0.0f) | (e2 == 0.0f);
                const bool inside = ((e0 >= 0.0f) & (e1 >= 0.0f) & (e2 >= 0.0f)) | ((e0 <= 0.0f) & (e1 <= 0.0f) & (e2 <= 0.0f));
                candidate[k] = zero | inside;
            }
            for (size_t k = 0; k < m; ++k) {
                if (!candidate[k]) continue;
                const uint32_t id = uint32_t(begin + k);
                const TriangleTest test = intersect_triangle(tris[id], ray, sheared, box_ray);
                if (test.hit && is_closer(test.t, id, best)) best = {id, test.t, test.u, test.v};
            }
        }
        answers[r] = best;
    });
    return answers;
}

/// The brute-force answer for every ray, computed in parallel. Semantically
/// BruteForce::intersect_closest: the smallest (t, id) among the triangles that
/// intersect_triangle() accepts on [t_min, t_max]; u, v of that triangle. The
/// triangle tests are laid out structure-of-arrays so the compiler vectorizes
/// them; IEEE arithmetic is element-wise, so each lane computes exactly what
/// intersect_triangle computes (same operations, same order, no contraction) up
/// to its inside test; a lane inside is then tested by intersect_triangle itself,
/// which adds the own-box rule. check_oracle() confirms that against BruteForce.
inline std::vector<Hit> brute_force_answers(const Mesh& mesh, const std::vector<Ray>& rays,
                                            TriangleTestKind kind = TriangleTestKind::MollerTrumbore) {
    if (kind == TriangleTestKind::Watertight) return brute_force_answers_watertight(mesh, rays);
    const TriangleArray tris = make_triangles(mesh);
    const size_t n = tris.size();
    std::vector<float> p0x(n), p0y(n), p0z(n), e1x(n), e1y(n), e1z(n), e2x(n), e2y(n), e2z(n);
    for (size_t i = 0; i < n; ++i) {
        p0x[i] = tris[i].p0.x; p0y[i] = tris[i].p0.y; p0z[i] = tris[i].p0.z;
        e1x[i] = tris[i].edge1.x; e1y[i] = tris[i].edge1.y; e1z[i] = tris[i].edge1.z;
        e2x[i] = tris[i].edge2.x; e2y[i] = tris[i].edge2.y; e2z[i] = tris[i].edge2.z;
    }
    std::vector<Hit> answers(rays.size());
    tbb::parallel_for(size_t(0), rays.size(), [&](size_t r) {
        const Ray& ray = rays[r];
        const BoxTestRay box_ray(ray);
        constexpr size_t kBlock = 512;
        unsigned char inside[kBlock];
        Hit best;
        for (size_t begin = 0; begin < n; begin += kBlock) {
            const size_t m = std::min(kBlock, n - begin);
            for (size_t k = 0; k < m; ++k) {  // intersect_triangle, one lane per triangle
                const size_t i = begin + k;
                const float px = ray.dir.y * e2z[i] - ray.dir.z * e2y[i];
                const float py = ray.dir.z * e2x[i] - ray.dir.x * e2z[i];
                const float pz = ray.dir.x * e2y[i] - ray.dir.y * e2x[i];
                const float det = e1x[i] * px + e1y[i] * py + e1z[i] * pz;
                const float inv_det = 1.0f / det;
                const float tx = ray.origin.x - p0x[i], ty = ray.origin.y - p0y[i], tz = ray.origin.z - p0z[i];
                const float u = (tx * px + ty * py + tz * pz) * inv_det;
                const float qx = ty * e1z[i] - tz * e1y[i];
                const float qy = tz * e1x[i] - tx * e1z[i];
                const float qz = tx * e1y[i] - ty * e1x[i];
                const float v = (ray.dir.x * qx + ray.dir.y * qy + ray.dir.z * qz) * inv_det;
                inside[k] = (det != 0.0f) & (u >= 0.0f) & (v >= 0.0f) & (u + v <= 1.0f);
            }
            for (size_t k = 0; k < m; ++k) {
                if (!inside[k]) continue;
                const uint32_t id = uint32_t(begin + k);
                const TriangleTest test = intersect_triangle(tris[id], ray, box_ray);
                if (test.hit && is_closer(test.t, id, best)) best = {id, test.t, test.u, test.v};
            }
        }
        answers[r] = best;
    });
    return answers;
}

/// Same triangle and bit-identical t, u, v (misses compare equal whatever t holds).
inline bool same_hit(const Hit& a, const Hit& b) {
    if (a.tri != b.tri) return false;
    if (!a.found()) return true;
    return std::bit_cast<uint32_t>(a.t) == std::bit_cast<uint32_t>(b.t) &&
           std::bit_cast<uint32_t>(a.u) == std::bit_cast<uint32_t>(b.u) &&
           std::bit_cast<uint32_t>(a.v) == std::bit_cast<uint32_t>(b.v);
}

inline std::string describe(const Ray& r) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "ray o=(%.9g, %.9g, %.9g) d=(%.9g, %.9g, %.9g) t in [%.9g, %.9g]", r.origin.x,
                  r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.t_min, r.t_max);
    return buf;
}

inline std::string describe(const Hit& h) {
    if (!h.found()) return "miss";
    char buf[128];
    std::snprintf(buf, sizeof buf, "tri %u t=%.9g u=%.9g v=%.9g", h.tri, h.t, h.u, h.v);
    return buf;
}

/// The rays the OBJ fuzzer traces through an input of `input_size` bytes: seeded by
/// the size, so a saved input replays exactly (and an edited one does not).
inline std::vector<Ray> fuzz_rays(const Mesh& mesh, size_t input_size) { return make_test_rays(mesh, 64, input_size); }

/// The first disagreement of any configuration (all_configurations) with brute
/// force on `rays`, as a message: another triangle or a t not bit-identical for
/// the closest hit, or another answer to "any hit?". nullopt when all agree.
/// (What the OBJ fuzzer checks on every input, and its corpus's test replays.)
inline std::optional<std::string> first_disagreement(const Mesh& mesh, const std::vector<Ray>& rays) {
    std::vector<Hit> answers[2];  // by TriangleTestKind
    for (TriangleTestKind kind : {TriangleTestKind::MollerTrumbore, TriangleTestKind::Watertight}) {
        const BruteForce brute(mesh, kind);
        for (const Ray& ray : rays) {
            NoObserver none;
            answers[int(kind)].push_back(brute.intersect_closest(ray, none));
        }
    }
    for (const auto& [label, config] : all_configurations()) {
        auto built = build_accelerator(mesh, config);
        if (!built) return label + " does not build: " + built.error();
        const std::vector<Hit>& want = answers[int(config.triangle_test)];
        for (size_t i = 0; i < rays.size(); ++i) {
            const Hit got = (*built)->intersect_closest(rays[i]);
            const bool same = got.tri == want[i].tri && std::bit_cast<uint32_t>(got.t) == std::bit_cast<uint32_t>(want[i].t);
            const bool any = (*built)->intersect_any(rays[i]);
            if (same && any == want[i].found()) continue;
            char ray_text[256];
            std::snprintf(ray_text, sizeof ray_text, "ray (%a %a %a) -> (%a %a %a) [%a, %a]", rays[i].origin.x,
                          rays[i].origin.y, rays[i].origin.z, rays[i].dir.x, rays[i].dir.y, rays[i].dir.z,
                          rays[i].t_min, rays[i].t_max);
            char hits[160];
            std::snprintf(hits, sizeof hits, "tri %u t %a (any-hit: %s), brute force tri %u t %a", got.tri, got.t,
                          any ? "hit" : "miss", want[i].tri, want[i].t);
            return label + " differs from brute force: " + ray_text + ": " + hits;
        }
    }
    return std::nullopt;
}

}  // namespace accelviz::test
