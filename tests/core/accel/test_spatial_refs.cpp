// split_reference, the KD tree's and octree's cut of a reference among a node's
// children: against the triangle clipped to each child on its own.
#include <gtest/gtest.h>

#include <cmath>

#include "core/accel/spatial_refs.h"
#include "core/geometry/triangle_box.h"
#include "core/util/random.h"

using namespace accelviz;

namespace {

/// True if a and b differ by at most one float step.
bool within_one_ulp(float a, float b) { return a == b || std::nextafter(a, b) == b; }

/// One random case: a cell, a triangle around it, and the reference the build would
/// hold for it in that cell (its part in the padded cell, grown by pad).
struct Case {
    Mesh mesh;
    Aabb cell;
    float pad;
    SpatialRef ref;
    bool valid = false;
};

Case random_case(Rng& rng) {
    Case c;
    Vec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
        const float x = rng.uniform(-10.0f, 10.0f), y = rng.uniform(-10.0f, 10.0f);
        lo[a] = std::fmin(x, y) - 0.5f;
        hi[a] = std::fmax(x, y) + 0.5f;
    }
    c.cell = {lo, hi};
    c.pad = reference_padding({Vec3{-12, -12, -12}, Vec3{12, 12, 12}});
    for (int k = 0; k < 3; ++k) {
        Vec3 p;
        for (int a = 0; a < 3; ++a) {
            const float extent = hi[a] - lo[a];
            p[a] = rng.uniform(lo[a] - 0.3f * extent, hi[a] + 0.3f * extent);
        }
        c.mesh.positions.push_back(p);
    }
    c.mesh.indices.push_back({0, 1, 2});
    const Aabb part = clip_triangle_to_box(c.mesh.positions[0], c.mesh.positions[1], c.mesh.positions[2],
                                           padded(c.cell, c.pad));
    if (part.empty()) return c;
    c.ref = {0, intersection(padded(part, c.pad), padded(c.cell, 2 * c.pad))};
    c.valid = !c.ref.box.empty();
    return c;
}

/// The child of `cell` cut at `planes` on `axes` (bit a of o: above on axis a).
Aabb child_box(const Aabb& cell, Vec3 planes, unsigned axes, int o) {
    Aabb child = cell;
    for (int a = 0; a < 3; ++a) {
        if (!(axes >> a & 1)) continue;
        if (o >> a & 1) child.lo[a] = planes[a];
        else child.hi[a] = planes[a];
    }
    return child;
}

/// Checks split_reference against clipping the triangle to each child on its own.
void expect_parts_match_own_clips(const Case& c, Vec3 planes, unsigned axes, ClipMode mode, int& clipped) {
    ChildRefs parts;
    split_reference(c.ref, c.mesh, c.cell, planes, axes, c.pad, mode, parts);
    int k = 0;
    for (int o = 0; o < 8; ++o) {
        if (o & ~int(axes)) continue;
        bool reached = true;  // the box rule: below iff lo < plane or not hi > plane, above iff hi > plane
        for (int a = 0; a < 3; ++a) {
            if (!(axes >> a & 1)) continue;
            const bool above = c.ref.box.hi[a] > planes[a];
            const bool below = c.ref.box.lo[a] < planes[a] || !above;
            reached = reached && ((o >> a & 1) ? above : below);
        }
        const Aabb child = child_box(c.cell, planes, axes, o);
        std::optional<Aabb> expected;
        if (reached) {
            const Aabb limit = padded(child, 2 * c.pad);
            if (limit.contains(c.ref.box)) {
                expected = c.ref.box;
            } else if (mode == ClipMode::Box) {
                expected = intersection(c.ref.box, limit);
            } else {
                ++clipped;
                const Aabb own = clip_triangle_to_box(c.mesh.positions[0], c.mesh.positions[1], c.mesh.positions[2],
                                                      padded(child, c.pad));
                if (!own.empty()) expected = intersection(padded(own, c.pad), c.ref.box);
            }
            if (expected && expected->empty()) expected.reset();
        }
        const bool got = k < parts.count && parts.child[k] == o;
        ASSERT_EQ(got, expected.has_value()) << "child " << o;
        if (!got) continue;
        const Aabb& box = parts.ref[k].box;
        EXPECT_EQ(parts.ref[k].tri, c.ref.tri);
        for (int a = 0; a < 3; ++a) {
            // The same part, clipped in another order: the same box up to a last-place step.
            EXPECT_TRUE(within_one_ulp(box.lo[a], expected->lo[a])) << "child " << o << " axis " << a;
            EXPECT_TRUE(within_one_ulp(box.hi[a], expected->hi[a])) << "child " << o << " axis " << a;
        }
        ++k;
    }
    EXPECT_EQ(k, parts.count) << "no parts beyond the children reached";
}

/// Random cases from `seed`, each split at the planes `split(case, i)` gives on `axes(i)`,
/// with both clip modes. Returns how many parts exact clipping had to cut.
template <class Planes, class Axes>
int check_random_cases(uint64_t seed, Planes&& split, Axes&& axes) {
    Rng rng(seed);
    int cases = 0, clipped = 0;
    for (int i = 0; i < 4000; ++i) {
        const Case c = random_case(rng);
        if (!c.valid) continue;
        ++cases;
        const Vec3 planes = split(c, i, rng);
        for (ClipMode mode : {ClipMode::Exact, ClipMode::Box})
            expect_parts_match_own_clips(c, planes, axes(i), mode, clipped);
    }
    EXPECT_GT(cases, 2000);
    return clipped;
}

TEST(SplitReference, KdSplitMatchesClippingEachSideOnItsOwn) {
    const int clipped = check_random_cases(
        11,
        [](const Case& c, int i, Rng& rng) {
            Vec3 planes;
            planes[i % 3] = rng.uniform(c.cell.lo[i % 3], c.cell.hi[i % 3]);
            return planes;
        },
        [](int i) { return 1u << (i % 3); });
    EXPECT_GT(clipped, 1000) << "most cases cut the triangle";
}

TEST(SplitReference, OctantSplitMatchesClippingEachOctantOnItsOwn) {
    const int clipped = check_random_cases(
        12, [](const Case& c, int, Rng&) { return c.cell.center(); }, [](int) { return 7u; });
    EXPECT_GT(clipped, 4000) << "most cases cut the triangle into several octants";
}

TEST(SplitReference, AReferenceInsideOneChildIsKeptWhole) {
    Mesh mesh;
    mesh.positions = {{0.1f, 0.1f, 0.1f}, {0.4f, 0.1f, 0.1f}, {0.1f, 0.4f, 0.3f}};
    mesh.indices = {{0, 1, 2}};
    const Aabb cell{{0, 0, 0}, {2, 2, 2}};
    const float pad = reference_padding(cell);
    const SpatialRef ref{0, padded(mesh.triangle_bounds(0), pad)};
    ChildRefs parts;
    split_reference(ref, mesh, cell, cell.center(), 7u, pad, ClipMode::Exact, parts);
    ASSERT_EQ(parts.count, 1);
    EXPECT_EQ(parts.child[0], 0);
    EXPECT_EQ(parts.ref[0].box.lo, ref.box.lo);
    EXPECT_EQ(parts.ref[0].box.hi, ref.box.hi);
}

}  // namespace
