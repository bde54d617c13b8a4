// split_reference and OctantSplit, the KD tree's and octree's cut of a reference among
// a node's children: against the triangle clipped to each child on its own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/accel/spatial_refs.h"
#include "core/geometry/morton_order.h"
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
void expect_parts_match_own_clips(const Case& c, Vec3 planes, unsigned axes, PartRule rule, int& clipped) {
    ChildRefs parts;
    split_reference(c.ref, corner_triples(c.mesh), c.cell, planes, axes, c.pad, rule, parts);
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
        Aabb expected;  // empty: the child gets nothing
        if (reached) {
            const Aabb limit = padded(child, 2 * c.pad);
            if (limit.contains(c.ref.box)) {
                expected = c.ref.box;
            } else if (rule == PartRule::BoxOverlap) {
                expected = intersection(c.ref.box, limit);
            } else {
                ++clipped;
                const Aabb own = clip_triangle_to_box(c.mesh.positions[0], c.mesh.positions[1], c.mesh.positions[2],
                                                      padded(child, c.pad));
                if (!own.empty()) expected = intersection(padded(own, c.pad), c.ref.box);
            }
        }
        const bool got = k < parts.count && parts.child[k] == o;
        ASSERT_EQ(got, !expected.empty()) << "child " << o;
        if (!got) continue;
        const Aabb& box = parts.ref[k].box;
        EXPECT_EQ(parts.ref[k].tri, c.ref.tri);
        for (int a = 0; a < 3; ++a) {
            // The same part, clipped in another order: the same box up to a last-place step.
            EXPECT_TRUE(within_one_ulp(box.lo[a], expected.lo[a])) << "child " << o << " axis " << a;
            EXPECT_TRUE(within_one_ulp(box.hi[a], expected.hi[a])) << "child " << o << " axis " << a;
        }
        ++k;
    }
    EXPECT_EQ(k, parts.count) << "no parts beyond the children reached";
}

/// Checks OctantSplit (the cell cut at its centre) against clipping the triangle to
/// each octant on its own: Clipped's octants, up to rounding well inside pad.
void expect_octants_match_own_clips(const Case& c, ClipMode mode, int& clipped) {
    const Vec3 centre = c.cell.center();
    const uint32_t got = OctantSplit(c.cell, c.pad, mode).reached(c.ref.box, corner_triples(c.mesh)[0]);
    for (int o = 0; o < 8; ++o) {
        bool reached = true;  // the box rule, as split_reference's
        for (int a = 0; a < 3; ++a) {
            const bool above = c.ref.box.hi[a] > centre[a];
            const bool below = c.ref.box.lo[a] < centre[a] || !above;
            reached = reached && ((o >> a & 1) ? above : below);
        }
        const Aabb child = child_box(c.cell, centre, 7u, o);
        const Aabb limit = padded(child, 2 * c.pad);
        if (reached && !limit.contains(c.ref.box)) {
            reached = !intersection(c.ref.box, limit).empty();
            if (reached && mode == ClipMode::Exact) {
                ++clipped;
                reached = !clip_triangle_to_box(c.mesh.positions[0], c.mesh.positions[1], c.mesh.positions[2],
                                                padded(child, c.pad))
                               .empty();
            }
        }
        EXPECT_EQ(bool(got >> o & 1), reached) << "octant " << o;
    }
}

/// Random cases from `seed`, each split at the planes `split(case, i)` gives on `axes(i)`,
/// by every rule. Returns how many parts the exact rules had to decide.
template <class Planes, class Axes>
int check_random_cases(uint64_t seed, Planes&& split, Axes&& axes) {
    Rng rng(seed);
    int cases = 0, clipped = 0;
    for (int i = 0; i < 4000; ++i) {
        const Case c = random_case(rng);
        if (!c.valid) continue;
        ++cases;
        const Vec3 planes = split(c, i, rng);
        for (PartRule rule : {PartRule::Clipped, PartRule::BoxOverlap})
            expect_parts_match_own_clips(c, planes, axes(i), rule, clipped);
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
    EXPECT_GT(clipped, 2000) << "most cases cut the triangle";
}

TEST(SplitReference, ThreeAxisSplitMatchesClippingEachOctantOnItsOwn) {
    const int clipped = check_random_cases(
        12, [](const Case& c, int, Rng&) { return c.cell.center(); }, [](int) { return 7u; });
    EXPECT_GT(clipped, 8000) << "most cases cut the triangle into several octants";
}

TEST(OctantSplit, MatchesClippingEachOctantOnItsOwn) {
    // Each case with four boxes: the tight one (the triangle clipped to the cell), the
    // octree's own (the triangle's padded box cut to the cell grown by 2·pad), and that
    // one with a side moved onto a centre plane, or flattened onto it: the ties of
    // "below iff lo < centre or not hi > centre, above iff hi > centre".
    Rng rng(13);
    int cases = 0, clipped = 0;
    for (int i = 0; i < 4000; ++i) {
        const Case c = random_case(rng);
        if (!c.valid) continue;
        const Vec3* p = c.mesh.positions.data();
        Case own = c;
        own.ref.box = intersection(padded(triangle_box(p[0], p[1], p[2]), c.pad), padded(c.cell, 2 * c.pad));
        const int a = i % 3;
        const float centre = c.cell.center()[a];
        Case side = own, flat = own;
        if (i % 2 == 0 && own.ref.box.lo[a] <= centre) side.ref.box.hi[a] = centre;
        if (i % 2 == 1 && own.ref.box.hi[a] >= centre) side.ref.box.lo[a] = centre;
        flat.ref.box.lo[a] = flat.ref.box.hi[a] = centre;
        const Case* versions[] = {&c, &own, &side, &flat};
        for (const Case* k : versions) {
            if (k->ref.box.empty()) continue;
            ++cases;
            for (ClipMode mode : {ClipMode::Exact, ClipMode::Box}) expect_octants_match_own_clips(*k, mode, clipped);
        }
    }
    EXPECT_GT(cases, 8000);
    EXPECT_GT(clipped, 15000) << "most cases need the triangle's own test in several octants";
}

TEST(SplitReference, AReferenceInsideOneChildIsKeptWhole) {
    Mesh mesh;
    mesh.positions = {{0.1f, 0.1f, 0.1f}, {0.4f, 0.1f, 0.1f}, {0.1f, 0.4f, 0.3f}};
    mesh.indices = {{0, 1, 2}};
    const Aabb cell{{0, 0, 0}, {2, 2, 2}};
    const float pad = reference_padding(cell);
    const SpatialRef ref{0, padded(mesh.triangle_bounds(0), pad)};
    ChildRefs parts;
    for (PartRule rule : {PartRule::Clipped, PartRule::BoxOverlap}) {
        split_reference(ref, corner_triples(mesh), cell, cell.center(), 7u, pad, rule, parts);
        ASSERT_EQ(parts.count, 1);
        EXPECT_EQ(parts.child[0], 0);
        EXPECT_EQ(parts.ref[0].box.lo, ref.box.lo);
        EXPECT_EQ(parts.ref[0].box.hi, ref.box.hi);
    }
    for (ClipMode mode : {ClipMode::Exact, ClipMode::Box})
        EXPECT_EQ(OctantSplit(cell, pad, mode).reached(ref.box, corner_triples(mesh)[0]), 1u);
}

}  // namespace

namespace {

TEST(TriangleAxes, AnswersAsTheSeparatingAxisTestOnRandomBoxes) {
    // One triangle against many boxes, as an octree tests its octants: the answers of the
    // shared axes must be triangle_overlaps_box's. Boxes near and around the triangle,
    // flat triangles and segments among them.
    Rng rng(21);
    int overlaps = 0, separate = 0;
    for (int i = 0; i < 3000; ++i) {
        Vec3 p[3];
        for (auto& v : p) v = {rng.uniform(-5.0f, 5.0f), rng.uniform(-5.0f, 5.0f), rng.uniform(-5.0f, 5.0f)};
        if (i % 10 == 0) p[2] = p[1];          // a segment
        if (i % 10 == 1) p[2][i % 3] = p[0][i % 3] = p[1][i % 3];  // in an axis plane
        const TriangleAxes axes(p[0], p[1], p[2]);
        for (int b = 0; b < 8; ++b) {
            // A small box about a point near the triangle (a point of it moved a little):
            // most boxes then lie near touching it, on either side.
            const float u = rng.uniform(0.0f, 1.0f), v = rng.uniform(0.0f, 1.0f - u);
            const Vec3 on = p[0] + (p[1] - p[0]) * u + (p[2] - p[0]) * v;
            Vec3 lo, hi;
            for (int a = 0; a < 3; ++a) {
                const float x = on[a] + rng.uniform(-0.5f, 0.5f);
                lo[a] = x - rng.uniform(0.0f, 0.4f);
                hi[a] = x + rng.uniform(0.0f, 0.4f);
            }
            const Aabb box{lo, hi};
            const bool expected = triangle_overlaps_box(p[0], p[1], p[2], box);
            ASSERT_EQ(axes.overlaps(box), expected) << "triangle " << i << " box " << b;
            (expected ? overlaps : separate)++;
        }
    }
    EXPECT_GT(overlaps, 2000);
    EXPECT_GT(separate, 2000);
}

TEST(MortonOrder, APermutationInCodeOrderTiesById) {
    Mesh mesh;
    Rng rng(5);
    for (int i = 0; i < 5000; ++i) {
        const Vec3 c{rng.uniform(0.0f, 1.0f), rng.uniform(0.0f, 1.0f), rng.uniform(0.0f, 1.0f)};
        const Vec3 d{0.001f, 0.0f, 0.0f};
        mesh.add_triangle(c, c + d, c + Vec3{0.0f, 0.001f, 0.0f});
        if (i % 7 == 0) mesh.add_triangle(c, c + d, c + Vec3{0.0f, 0.0f, 0.001f});  // the same centre cell
    }
    const Aabb bounds = mesh.bounds();
    const std::vector<uint32_t> order = morton_order(mesh, bounds);
    ASSERT_EQ(order.size(), mesh.triangle_count());
    std::vector<char> seen(order.size(), 0);
    for (uint32_t t : order) {
        ASSERT_LT(t, order.size());
        ASSERT_FALSE(seen[t]) << "triangle " << t << " twice";
        seen[t] = 1;
    }
    const auto code = [&](uint32_t t) {
        const Vec3 c = mesh.triangle_bounds(t).center();
        uint32_t cell[3];
        for (int a = 0; a < 3; ++a)
            cell[a] = std::min(1023u, uint32_t((c[a] - bounds.lo[a]) / (bounds.hi[a] - bounds.lo[a]) * 1024.0f));
        return morton_code(cell[0], cell[1], cell[2]);
    };
    for (size_t k = 1; k < order.size(); ++k) {
        const uint32_t a = code(order[k - 1]), b = code(order[k]);
        ASSERT_TRUE(a < b || (a == b && order[k - 1] < order[k])) << "at " << k;
    }
    EXPECT_EQ(morton_code(1, 0, 0), 1u);
    EXPECT_EQ(morton_code(0, 1, 0), 2u);
    EXPECT_EQ(morton_code(0, 0, 1), 4u);
    EXPECT_EQ(morton_code(1023, 1023, 1023), (1u << 30) - 1);
}

}  // namespace
