#pragma once
/// Four triangles tested against one ray by one instruction sequence: the lesson of
/// the wide nodes' boxes (box_lanes.h) applied to the wide BVH's leaves, as Embree's
/// four-triangle leaves do (Wald et al., "Embree: A Kernel Framework for Efficient
/// CPU Ray Tracing", 2014). A leaf of up to four triangles costs about one test.
/// The wide BVH and the KD tree keep their leaves this way.
///
/// Layout (LeafTriangleLanes): each leaf's triangles as structure of arrays, in leaf
/// order, in the space the leaf's Triangles take: for a leaf of c triangles that
/// starts at leaf-order index f, component q of its j-th triangle (q = p0.x, p0.y,
/// p0.z, edge1.x, ..., edge2.z) is floats[9 f + q c + j]. So a leaf is found by the
/// index the tree already has, and four lanes of one component are one (unaligned)
/// load; lanes past the leaf's end read the next component and are masked off.
///
/// Exactness: the lanes compute Möller–Trumbore's det, u, v and t with the operations
/// of intersect_triangle (triangle.h), in the same order, one IEEE operation per lane
/// (no fused multiply-add: the build passes -ffp-contract=off), so each lane holds
/// what the one-triangle test computes, bit for bit. Only a candidate (det != 0 and
/// u, v inside) goes on to finish_moller_trumbore, one triangle at a time, in leaf
/// order, with the closest hit so far: the calls intersect_triangle makes. So a leaf
/// tested four lanes at a time reports the same hits, and the same TriangleTest for
/// every triangle, as the leaf tested triangle by triangle.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/geometry/triangle.h"
#include "core/math/box_lanes.h"
#include "core/util/large_array.h"

namespace accelviz {

/// The first half of Möller–Trumbore on four lanes: what intersect_triangle computes
/// before its own-box rule (finish_moller_trumbore).
struct LaneTests {
    alignas(16) float t[4];
    alignas(16) float u[4];
    alignas(16) float v[4];
    uint32_t nonzero_det = 0;  ///< bit i: lane i's det != 0 (NaN counts: the test goes on, and fails)
    uint32_t candidates = 0;   ///< bit i: det != 0 and u >= 0, v >= 0, u + v <= 1

    /// Lane i as intersect_triangle has it before the own-box rule: no hit yet, t, u,
    /// v (or the default TriangleTest when det == 0).
    TriangleTest lane(int i) const {
        TriangleTest r;
        if (!(nonzero_det >> i & 1)) return r;
        r.t = t[i];
        r.u = u[i];
        r.v = v[i];
        return r;
    }
};

/// Triangles a leaf tests together with `test`: four lanes with Möller–Trumbore, one
/// at a time with the watertight test (its leaves are not kept as lanes). The wide
/// BVH's and the KD tree's SAH count tests of this many (sah.h, kd_sah.h).
constexpr int leaf_lanes_for(TriangleTestKind test) { return test == TriangleTestKind::MollerTrumbore ? 4 : 1; }

/// Every leaf's triangles as structure of arrays (see the layout above).
struct LeafTriangleLanes {
    static constexpr int kLanes = leaf_lanes_for(TriangleTestKind::MollerTrumbore);
    static constexpr int kComponents = 9;
    /// kLanes floats of padding at the end: the last leaf's last lanes read them.
    std::vector<float, LargeArrayAllocator<float>> floats;

    /// Sized for `triangle_count` triangles in leaf order.
    void resize(size_t triangle_count) { floats.assign(kComponents * triangle_count + kLanes, 0.0f); }
    /// Places triangle `tri` as the j-th of the leaf [first, first + count).
    void set(uint32_t first, uint32_t count, uint32_t j, const Triangle& tri) {
        float* leaf = floats.data() + size_t(kComponents) * first;
        const float values[kComponents] = {tri.p0.x,    tri.p0.y,    tri.p0.z,    tri.edge1.x, tri.edge1.y,
                                           tri.edge1.z, tri.edge2.x, tri.edge2.y, tri.edge2.z};
        for (int q = 0; q < kComponents; ++q) leaf[size_t(q) * count + j] = values[q];
    }
    /// The j-th triangle of the leaf [first, first + count), as stored.
    Triangle get(uint32_t first, uint32_t count, uint32_t j) const {
        const float* c = floats.data() + size_t(kComponents) * first + j;
        return {{c[0], c[count], c[2 * count]},
                {c[3 * count], c[4 * count], c[5 * count]},
                {c[6 * count], c[7 * count], c[8 * count]}};
    }
    const float* leaf(uint32_t first) const { return floats.data() + size_t(kComponents) * first; }
    size_t memory_bytes() const { return floats.size() * sizeof(float); }
};

/// Möller–Trumbore's first half on triangles j .. j + 3 of a leaf of `count` whose
/// lanes start at `leaf` (LeafTriangleLanes::leaf): lanes at or past `count` hold
/// whatever follows and must be masked off by the caller.
template <class Lanes>
[[gnu::always_inline]] inline LaneTests moller_trumbore_lanes(const float* leaf, uint32_t count, uint32_t j,
                                                              const Ray& ray) {
    static_assert(Lanes::kWidth == 4);
    auto at = [&](int q) { return Lanes::load_unaligned(leaf + size_t(q) * count + j); };
    auto splat = [](float x) { return Lanes::splat(x); };
    const Lanes e1x = at(3), e1y = at(4), e1z = at(5);
    const Lanes e2x = at(6), e2y = at(7), e2z = at(8);
    const Lanes dx = splat(ray.dir.x), dy = splat(ray.dir.y), dz = splat(ray.dir.z);
    // pvec = cross(dir, edge2); det = dot(edge1, pvec)
    const Lanes px = dy * e2z - dz * e2y, py = dz * e2x - dx * e2z, pz = dx * e2y - dy * e2x;
    const Lanes det = e1x * px + e1y * py + e1z * pz;
    const Lanes inv_det = splat(1.0f) / det;
    // tvec = origin - p0; u = dot(tvec, pvec) / det
    const Lanes tx = splat(ray.origin.x) - at(0), ty = splat(ray.origin.y) - at(1), tz = splat(ray.origin.z) - at(2);
    const Lanes u = (tx * px + ty * py + tz * pz) * inv_det;
    // qvec = cross(tvec, edge1); v = dot(dir, qvec) / det; t = dot(edge2, qvec) / det
    const Lanes qx = ty * e1z - tz * e1y, qy = tz * e1x - tx * e1z, qz = tx * e1y - ty * e1x;
    const Lanes v = (dx * qx + dy * qy + dz * qz) * inv_det;
    const Lanes t = (e2x * qx + e2y * qy + e2z * qz) * inv_det;
    LaneTests r;
    u.store(r.u);
    v.store(r.v);
    t.store(r.t);
    const Lanes zero = splat(0.0f);
    r.nonzero_det = ~Lanes::equal(det, zero) & 0xfu;
    r.candidates = r.nonzero_det & Lanes::less_equal(zero, u) & Lanes::less_equal(zero, v) &
                   Lanes::less_equal(u + v, splat(1.0f));
    return r;
}

/// The leaf loop of every tree whose leaves are lanes: for the leaf [first, first +
/// count), Möller–Trumbore's first half on four triangles at a time, then, in leaf
/// order, visit(k, result) for its k-th triangle, where result() is the TriangleTest
/// intersect_triangle gives that triangle against `ray` as it is then (a candidate
/// finished by finish_moller_trumbore with the closest hit so far in ray.t_max).
/// Every triangle is visited when `every_triangle` (an observer hears each test, a
/// mailbox records each id), else only the candidates: no other lane can hit. visit
/// returns true to end the leaf (any-hit found one); so does this, then.
template <class Lanes, class Visit>
[[gnu::always_inline]] inline bool for_each_lane_test(const LeafTriangleLanes& lanes, uint32_t first, uint32_t count,
                                                      const Ray& ray, const BoxTestRay& box_ray, bool every_triangle,
                                                      Visit&& visit) {
    const float* leaf = lanes.leaf(first);
    for (uint32_t j = 0; j < count; j += LeafTriangleLanes::kLanes) {
        const uint32_t in_leaf = (1u << std::min<uint32_t>(count - j, LeafTriangleLanes::kLanes)) - 1;
        const LaneTests test4 = moller_trumbore_lanes<Lanes>(leaf, count, j, ray);
        for (uint32_t todo = every_triangle ? in_leaf : test4.candidates & in_leaf; todo; todo &= todo - 1) {
            const int i = __builtin_ctz(todo);
            const uint32_t k = j + uint32_t(i);
            const auto result = [&]() __attribute__((always_inline)) {
                TriangleTest test = test4.lane(i);
                if (test4.candidates >> i & 1) finish_moller_trumbore(lanes.get(first, count, k), ray, box_ray, test);
                return test;
            };
            if (visit(k, result)) return true;
        }
    }
    return false;
}

}  // namespace accelviz
