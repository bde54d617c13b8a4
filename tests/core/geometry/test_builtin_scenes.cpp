// Built-in scenes: triangle counts, the property each scene exists for (equal
// centroids, equal boxes, a teapot in a stadium), determinism, and the errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>

#include "core/geometry/scene.h"

using namespace accelviz;

namespace {

Mesh make(const std::string& spec) {
    auto mesh = make_builtin(spec);
    EXPECT_TRUE(mesh.ok()) << spec << ": " << mesh.error();
    return mesh.ok() ? *mesh : Mesh{};
}

void expect_contains(const std::string& text, const std::string& part) {
    EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' not in: " << text;
}

/// How many triangles use each undirected edge (by vertex index).
std::map<std::pair<uint32_t, uint32_t>, int> edge_uses(const Mesh& mesh) {
    std::map<std::pair<uint32_t, uint32_t>, int> uses;
    for (const auto& tri : mesh.indices)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = tri[k], b = tri[(k + 1) % 3];
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    return uses;
}

/// Every edge shared by exactly two triangles.
bool is_closed(const Mesh& mesh) {
    for (const auto& [edge, count] : edge_uses(mesh))
        if (count != 2) return false;
    return true;
}

Vec3 normal(const Mesh& mesh, size_t t) {
    const Triangle tri = mesh.triangle(t);
    return cross(tri.edge1, tri.edge2);
}

Vec3 centroid(const Mesh& mesh, size_t t) {
    return (mesh.vertex(t, 0) + mesh.vertex(t, 1) + mesh.vertex(t, 2)) / 3.0f;
}

/// The closest hit of `ray` by testing every triangle (no structure needed here).
Hit brute_force(const Mesh& mesh, const Ray& ray) {
    Hit best;
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        const TriangleTest r = intersect_triangle(mesh.triangle(t), ray);
        if (r.hit && is_closer(r.t, uint32_t(t), best)) best = {uint32_t(t), r.t, r.u, r.v};
    }
    return best;
}

}  // namespace

// ---------------------------------------------------------------------------
// Every scene
// ---------------------------------------------------------------------------

TEST(BuiltinScenes, TriangleCounts) {
    const std::pair<const char*, size_t> expected[] = {
        {"cube", 12},
        {"cornell", 32},
        {"teapot", 56 * 8 * 8 - 4 * 8},  // 28 patches x 2n^2, minus n collapsed triangles per lid-knob patch
        {"teapot?n=1", 56 - 4},
        {"teapot?n=13", 56 * 13 * 13 - 4 * 13},
        {"sphere", 20 * 64},
        {"sphere?subdiv=0", 20},
        {"sphere?subdiv=2", 20 * 16},
        {"stadium", 56 * 12 * 12 - 4 * 12 + 66},
        {"stadium?n=2&size=7.5", 56 * 4 - 8 + 66},
        {"same-centroid", 1000},
        {"same-centroid?n=17", 17},
        {"same-box", 1000},
        {"same-box?seed=3&n=5", 5},
        {"soup", 1000},
        {"soup?n=12345&seed=7", 12345},
        {"empty", 0},
        {"single", 1},
        {"kd-challenge", 2},
        {"twenty-two", 22},
        {"cornell-mirror", 32},
        {"moving", 32 + 56 * 8 * 8 - 4 * 8},
        {"moving?t=0.3&n=2", 32 + 56 * 4 - 8},
        {"wave?mesh=builtin:cube&t=0.5", 12},
    };
    for (const auto& [spec, count] : expected) {
        const Mesh mesh = make(spec);
        EXPECT_EQ(mesh.triangle_count(), count) << spec;
        EXPECT_EQ(mesh.name, std::string("builtin:") + spec);
    }
}

TEST(BuiltinScenes, EveryListedSceneBuildsWithItsDefaultsAndIsWellFormed) {
    ASSERT_EQ(builtin_scenes().size(), 17u);
    for (const BuiltinInfo& info : builtin_scenes()) {
        SCOPED_TRACE(info.name);
        EXPECT_FALSE(info.description.empty());
        EXPECT_EQ(info.description.find('\n'), std::string::npos);
        const Mesh mesh = make(info.name);
        for (const auto& tri : mesh.indices)
            for (uint32_t i : tri) ASSERT_LT(i, mesh.positions.size());
        for (const Vec3& p : mesh.positions)
            ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    }
}

TEST(BuiltinScenes, DescriptionsNameTheParameters) {
    std::map<std::string, std::string> by_name;
    for (const BuiltinInfo& info : builtin_scenes()) by_name[info.name] = info.description;
    expect_contains(by_name["teapot"], "n (integer 1..64, default 8)");
    expect_contains(by_name["sphere"], "subdiv (integer 0..7, default 3)");
    expect_contains(by_name["stadium"], "size (number");
    expect_contains(by_name["soup"], "seed (integer");
    expect_contains(by_name["cube"], "no parameters");
}

TEST(BuiltinScenes, SameSpecGivesBitIdenticalMeshes) {
    for (const char* spec : {"soup?n=500&seed=42", "same-centroid?n=300&seed=9", "same-box?n=300&seed=9", "teapot?n=5",
                             "sphere?subdiv=3", "stadium?n=3", "cornell", "moving?t=0.37", "wave?t=0.61&height=0.3"}) {
        SCOPED_TRACE(spec);
        const Mesh a = make(spec), b = make(spec);
        EXPECT_EQ(a.positions, b.positions);
        EXPECT_EQ(a.indices, b.indices);
    }
}

TEST(BuiltinScenes, DifferentSeedsGiveDifferentTriangles) {
    for (const char* name : {"soup", "same-centroid", "same-box"}) {
        SCOPED_TRACE(name);
        const Mesh a = make(std::string(name) + "?n=50&seed=1"), b = make(std::string(name) + "?n=50&seed=2");
        EXPECT_NE(a.positions, b.positions);
        // The first triangles of a longer run are the same run: n only says when to stop.
        const Mesh longer = make(std::string(name) + "?n=80&seed=1");
        EXPECT_TRUE(std::equal(a.positions.begin(), a.positions.end(), longer.positions.begin()));
    }
}

TEST(BuiltinScenes, SeededOutputIsPinned) {
    // Guards "identical on every machine": these numbers come from Rng and float
    // arithmetic only. If they change, every seeded scene in saved presets changes.
    const Mesh soup = make("soup?n=1&seed=1");
    ASSERT_EQ(soup.positions.size(), 3u);
    const Mesh again = make("soup?n=1&seed=1");
    EXPECT_EQ(soup.positions, again.positions);
    EXPECT_EQ(soup.positions[0], (Vec3{0x1.0b365p-3f, 0x1.021388p-1f, 0x1.eb7cbp-1f}));
    EXPECT_EQ(soup.positions[2], (Vec3{0x1.074ec6p-3f, 0x1.fc7d8ap-2f, 0x1.e135e2p-1f}));
}

// ---------------------------------------------------------------------------
// Each scene's own property
// ---------------------------------------------------------------------------

TEST(BuiltinScenes, CubeIsClosedWithOutwardNormals) {
    const Mesh cube = make("cube");
    EXPECT_EQ(cube.positions.size(), 8u);
    EXPECT_EQ(cube.bounds(), (Aabb{{-1, -1, -1}, {1, 1, 1}}));
    EXPECT_TRUE(is_closed(cube));
    for (size_t t = 0; t < cube.triangle_count(); ++t) {
        EXPECT_GT(dot(normal(cube, t), centroid(cube, t)), 0.0f) << "triangle " << t;
        const Vec3 n = normal(cube, t);  // each lies in a face plane: its normal is an axis
        EXPECT_EQ((n.x != 0) + (n.y != 0) + (n.z != 0), 1) << "triangle " << t;
    }
}

TEST(BuiltinScenes, SphereIsAClosedUnitIcosphere) {
    for (int subdiv = 0; subdiv <= 3; ++subdiv) {
        SCOPED_TRACE(subdiv);
        const Mesh sphere = make("sphere?subdiv=" + std::to_string(subdiv));
        // V - E + F = 2 for a closed genus-0 mesh: V = 10 * 4^s + 2.
        EXPECT_EQ(sphere.positions.size(), 10u * (1u << (2 * subdiv)) + 2u);
        EXPECT_TRUE(is_closed(sphere));
        for (const Vec3& p : sphere.positions) EXPECT_NEAR(length(p), 1.0f, 1e-6f);
        for (size_t t = 0; t < sphere.triangle_count(); ++t)
            EXPECT_GT(dot(normal(sphere, t), centroid(sphere, t)), 0.0f) << "triangle " << t;
    }
}

TEST(BuiltinScenes, CornellBoxIsOpenInFrontAndLitFromAbove) {
    const Mesh box = make("cornell");
    const Aabb bounds = box.bounds();
    EXPECT_EQ(bounds.lo, (Vec3{0, 0, 0}));
    EXPECT_NEAR(bounds.hi.x, 5.56f, 1e-5f);
    EXPECT_NEAR(bounds.hi.y, 5.488f, 1e-5f);
    EXPECT_NEAR(bounds.hi.z, 5.592f, 1e-5f);

    // Looking in through the open front (+z), past the blocks: the back wall at z = 0.
    const Hit back = brute_force(box, Ray{{2.78f, 5.0f, 20.0f}, {0, 0, -1}});
    ASSERT_TRUE(back.found());
    EXPECT_NEAR(back.t, 20.0f, 1e-4f);
    // Straight down beside the blocks: the floor. Straight up from the middle: the light.
    const Hit floor = brute_force(box, Ray{{0.3f, 1.0f, 5.0f}, {0, -1, 0}});
    ASSERT_TRUE(floor.found());
    EXPECT_NEAR(floor.t, 1.0f, 1e-5f);
    const Hit light = brute_force(box, Ray{{2.78f, 4.0f, 2.8f}, {0, 1, 0}});
    ASSERT_TRUE(light.found());
    EXPECT_NEAR(light.t, 5.388f - 4.0f, 1e-4f);  // 1 cm under the ceiling at 5.488
    EXPECT_LT(normal(box, light.tri).y, 0.0f);    // the light faces down
    // The blocks: the tall one (3.30 high) on the left at the back, the short one (1.65) right, front.
    const Hit tall = brute_force(box, Ray{{1.87f, 5.0f, 2.1f}, {0, -1, 0}});
    ASSERT_TRUE(tall.found());
    EXPECT_NEAR(tall.t, 5.0f - 3.30f, 1e-4f);
    const Hit short_block = brute_force(box, Ray{{3.70f, 5.0f, 3.90f}, {0, -1, 0}});
    ASSERT_TRUE(short_block.found());
    EXPECT_NEAR(short_block.t, 5.0f - 1.65f, 1e-4f);
}

TEST(BuiltinScenes, TeapotStandsUprightOnTheFloor) {
    const Mesh teapot = make("teapot");
    const Aabb box = teapot.bounds();
    EXPECT_EQ(box.lo.y, 0.0f);  // the bottom rim sits exactly on y = 0
    EXPECT_NEAR(box.hi.y, 0.75f, 1e-4f);
    // Body radius 0.5 around the y axis; handle towards -x, spout towards +x.
    EXPECT_NEAR(box.lo.z, -0.5f, 1e-4f);
    EXPECT_NEAR(box.hi.z, 0.5f, 1e-4f);
    EXPECT_NEAR(box.lo.x, -0.75f, 1e-3f);
    EXPECT_GT(box.hi.x, 0.8f);
    EXPECT_LT(box.hi.x, 0.89f);
    // Upright: the highest point is the lid knob's top, on the axis.
    const auto top = std::max_element(teapot.positions.begin(), teapot.positions.end(),
                                      [](Vec3 a, Vec3 b) { return a.y < b.y; });
    EXPECT_NEAR(top->x, 0.0f, 1e-6f);
    EXPECT_NEAR(top->z, 0.0f, 1e-6f);
    // A ray straight down the axis hits the knob top first.
    const Hit knob = brute_force(teapot, Ray{{0.001f, 5, 0.001f}, {0, -1, 0}});
    ASSERT_TRUE(knob.found());
    EXPECT_NEAR(knob.t, 5.0f - 0.75f, 1e-3f);
}

TEST(BuiltinScenes, TeapotSeamsAreWeldedAndPolesDropped) {
    for (int n : {2, 5, 8}) {  // (at n = 1 the two handle patches are one quad each, on the same 4 corners)
        SCOPED_TRACE(n);
        const Mesh teapot = make("teapot?n=" + std::to_string(n));
        for (const auto& tri : teapot.indices) EXPECT_TRUE(tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2]);
        // Edges used once are the openings only: bottom rim (4 patches), inner rim
        // under the lid (4), lid's outer edge (4), handle ends (2 x 2), spout base
        // and tip (2 x 2); n edges each. An unwelded seam would add 2n per seam.
        int open_edges = 0;
        for (const auto& [edge, count] : edge_uses(teapot)) {
            EXPECT_LE(count, 2);
            open_edges += count == 1;
        }
        EXPECT_EQ(open_edges, 20 * n);
    }
}

TEST(BuiltinScenes, BezierPatchPassesThroughItsCorners) {
    const BezierPatch* patches = teapot_patches();
    for (int p = 0; p < kTeapotPatchCount; ++p) {
        const BezierPatch& patch = patches[p];
        EXPECT_EQ(bezier_patch_point(patch, 0, 0), patch.control[0][0]) << p;
        EXPECT_EQ(bezier_patch_point(patch, 1, 0), patch.control[3][0]) << p;
        EXPECT_EQ(bezier_patch_point(patch, 0, 1), patch.control[0][3]) << p;
        EXPECT_EQ(bezier_patch_point(patch, 1, 1), patch.control[3][3]) << p;
    }
    // A flat patch with control points on a regular grid is the bilinear map.
    BezierPatch flat;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) flat.control[i][j] = {float(i), float(j), 0};
    const Vec3 p = bezier_patch_point(flat, 0.25, 0.5);
    EXPECT_FLOAT_EQ(p.x, 0.75f);
    EXPECT_FLOAT_EQ(p.y, 1.5f);
}

TEST(BuiltinScenes, StadiumIsATinyTeapotInAHugeSparseScene) {
    const Mesh stadium = make("stadium");
    const Aabb box = stadium.bounds();
    EXPECT_EQ(box.lo, (Vec3{-50, 0, -50}));
    EXPECT_EQ(box.hi.x, 50.0f);
    EXPECT_EQ(box.hi.z, 50.0f);
    EXPECT_NEAR(box.hi.y, 6.0f, 1e-4f);
    size_t in_teapot = 0, large = 0;
    Aabb teapot;
    for (size_t t = 0; t < stadium.triangle_count(); ++t) {
        const Aabb b = stadium.triangle_bounds(t);
        const Vec3 e = b.extent();
        if (std::max({e.x, e.y, e.z}) < 0.5f) {
            ++in_teapot;
            teapot.grow(b);
        } else {
            ++large;
        }
    }
    EXPECT_EQ(in_teapot, 56u * 144u - 48u);
    EXPECT_EQ(large, 66u);
    EXPECT_NEAR(teapot.extent().y, 1.0f, 1e-3f);  // height ~1, on the floor in the middle
    EXPECT_EQ(teapot.lo.y, 0.0f);
    EXPECT_LT(std::max(std::abs(teapot.lo.x), teapot.hi.x), 1.2f);
    // A uniform grid of 32^3 cells over the scene: the teapot's box overlaps at most
    // 2 x 6 x 2 of the 32768 cells (it is 1/50 as wide as the scene, 1/6 as high).
    const Vec3 cell = box.extent() / 32.0f;
    size_t teapot_cells = 1;
    for (int axis = 0; axis < 3; ++axis) {
        const int first = int((teapot.lo[axis] - box.lo[axis]) / cell[axis]);
        const int last = int((teapot.hi[axis] - box.lo[axis]) / cell[axis]);
        teapot_cells *= size_t(last - first + 1);
    }
    EXPECT_LE(teapot_cells, 2u * 6u * 2u);
}

TEST(BuiltinScenes, SameCentroidCentroidsAreExactlyTheOrigin) {
    const Mesh mesh = make("same-centroid?n=2000&seed=5");
    std::set<std::array<float, 9>> distinct;
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        const Vec3 a = mesh.vertex(t, 0), b = mesh.vertex(t, 1), c = mesh.vertex(t, 2);
        // Exact in any summation order, and so is the mean.
        ASSERT_EQ((a + b) + c, (Vec3{0, 0, 0})) << t;
        ASSERT_EQ(a + (b + c), (Vec3{0, 0, 0})) << t;
        ASSERT_EQ((a + c) + b, (Vec3{0, 0, 0})) << t;
        ASSERT_EQ(centroid(mesh, t), (Vec3{0, 0, 0})) << t;
        ASSERT_GT(length(normal(mesh, t)), 0.0f) << "degenerate triangle " << t;
        distinct.insert({a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z});
    }
    EXPECT_EQ(distinct.size(), mesh.triangle_count());
    // Random sizes: the largest triangle is many times the smallest.
    float smallest = kInfinity, largest = 0;
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        const float extent = mesh.triangle_bounds(t).extent().x + mesh.triangle_bounds(t).extent().y;
        smallest = std::min(smallest, extent);
        largest = std::max(largest, extent);
    }
    EXPECT_GT(largest, 5 * smallest);
}

TEST(BuiltinScenes, SameBoxBoxesAreExactlyEqual) {
    const Mesh mesh = make("same-box?n=2000&seed=5");
    const Aabb expected{{-1.0f, -0.5f, -0.75f}, {1.0f, 0.5f, 0.75f}};
    std::set<std::array<float, 9>> distinct;
    std::set<std::array<float, 3>> centroids;
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        ASSERT_EQ(mesh.triangle_bounds(t), expected) << "triangle " << t;
        const Vec3 a = mesh.vertex(t, 0), b = mesh.vertex(t, 1), c = mesh.vertex(t, 2);
        distinct.insert({a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z});
        const Vec3 m = centroid(mesh, t);
        centroids.insert({m.x, m.y, m.z});
    }
    EXPECT_EQ(distinct.size(), mesh.triangle_count());
    EXPECT_GT(centroids.size(), mesh.triangle_count() * 9 / 10);  // the centroids still differ
}

TEST(BuiltinScenes, SoupTrianglesAreSmallAndSpreadOut) {
    const Mesh soup = make("soup?n=4000&seed=3");
    const Aabb allowed{{-1.1f, -1.1f, -1.1f}, {1.1f, 1.1f, 1.1f}};
    EXPECT_TRUE(allowed.contains(soup.bounds()));
    int octant_count[8] = {};
    float smallest = kInfinity, largest = 0;
    for (size_t t = 0; t < soup.triangle_count(); ++t) {
        const Vec3 e = soup.triangle_bounds(t).extent();
        const float size = std::max({e.x, e.y, e.z});
        EXPECT_LE(size, 0.2f);
        smallest = std::min(smallest, size);
        largest = std::max(largest, size);
        const Vec3 c = centroid(soup, t);
        ++octant_count[(c.x > 0) | (c.y > 0) << 1 | (c.z > 0) << 2];
    }
    EXPECT_GT(largest, 5 * smallest);
    for (int count : octant_count) EXPECT_NEAR(count, 500, 120);  // uniform centres: ~1/8 each
}

TEST(BuiltinScenes, EmptyAndSingle) {
    const Mesh empty = make("empty");
    EXPECT_EQ(empty.triangle_count(), 0u);
    EXPECT_TRUE(empty.bounds().empty());
    const Mesh single = make("single");
    ASSERT_EQ(single.triangle_count(), 1u);
    EXPECT_GT(normal(single, 0).z, 0.0f);  // faces the default camera
}

// ---------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------

TEST(BuiltinScenes, UnknownNameListsTheKnownOnes) {
    auto mesh = make_builtin("teapots");
    ASSERT_FALSE(mesh.ok());
    expect_contains(mesh.error(), "builtin:teapots");
    expect_contains(mesh.error(), "unknown built-in scene 'teapots'");
    for (const BuiltinInfo& info : builtin_scenes()) expect_contains(mesh.error(), info.name);
    EXPECT_FALSE(make_builtin("").ok());
    EXPECT_FALSE(load_scene("builtin:").ok());
    EXPECT_FALSE(make_builtin("?n=3").ok());
    EXPECT_FALSE(make_builtin("CUBE").ok());
}

TEST(BuiltinScenes, BadParametersSayWhatIsAccepted) {
    const std::pair<const char*, const char*> cases[] = {
        {"soup?n=abc", "n=abc is not a non-negative integer"},
        {"soup?n=-5", "n=-5 is not a non-negative integer"},
        {"soup?n=2.5", "n=2.5 is not"},
        {"soup?n=", "n= is not"},
        {"soup?n=0", "n=0 is out of range"},
        {"soup?seed=18446744073709551616", "out of range"},
        {"teapot?n=65", "n=65 is out of range"},
        {"sphere?subdiv=8", "subdiv=8 is out of range"},
        {"stadium?size=abc", "size=abc is not a number"},
        {"stadium?size=nan", "size=nan is not a number"},
        {"stadium?size=inf", "size=inf is not a number"},
        {"stadium?size=1", "size=1 is out of range"},
        {"teapot?m=3", "unknown parameter 'm'"},
        {"teapot?n", "parameter 'n' has no value"},
        {"teapot?n=3&n=4", "parameter 'n' given twice"},
        {"teapot?n=3&", "empty parameter"},
        {"teapot?&n=3", "empty parameter"},
        {"soup?n=3&&seed=2", "empty parameter"},
        {"soup?=3", "empty parameter name in '=3'"},
        {"cube?n=3", "cube takes no parameters"},
    };
    for (const auto& [spec, reason] : cases) {
        SCOPED_TRACE(spec);
        auto mesh = make_builtin(spec);
        ASSERT_FALSE(mesh.ok());
        expect_contains(mesh.error(), std::string("builtin:") + spec + ": ");
        expect_contains(mesh.error(), reason);
        EXPECT_EQ(mesh.error().find('\n'), std::string::npos);
    }
    auto soup = make_builtin("soup?n=abc");
    ASSERT_FALSE(soup.ok());
    expect_contains(soup.error(), "soup accepts n (integer 1..10000000, default 1000), seed (integer");
}

TEST(BuiltinScenes, ParametersAtTheEdgesOfTheirRanges) {
    EXPECT_TRUE(make_builtin("teapot?n=64").ok());
    EXPECT_TRUE(make_builtin("sphere?subdiv=0").ok());
    EXPECT_TRUE(make_builtin("stadium?size=5&n=1").ok());
    EXPECT_TRUE(make_builtin("stadium?size=1e5").ok());
    EXPECT_TRUE(make_builtin("soup?seed=0&n=1").ok());
    EXPECT_TRUE(make_builtin("soup?seed=18446744073709551615&n=1").ok());
    EXPECT_TRUE(make_builtin("teapot?").ok());  // an empty query is no parameters
}

TEST(BuiltinScenes, InstancesRepeatAMeshOnAGridWithoutOverlap) {
    const Mesh one = make("teapot?n=2");
    const Mesh many = make("instances?mesh=builtin:teapot?n=2&nx=3&nz=2");
    ASSERT_EQ(many.triangle_count(), 6 * one.triangle_count());
    ASSERT_EQ(many.positions.size(), 6 * one.positions.size());
    const Aabb box = one.bounds();
    const float step_x = 1.1f * box.extent().x, step_z = 1.1f * box.extent().z;
    for (size_t copy = 0; copy < 6; ++copy) {
        const Vec3 offset{float(copy % 3) * step_x, 0.0f, float(copy / 3) * step_z};
        for (size_t i = 0; i < one.positions.size(); ++i)
            ASSERT_EQ(many.positions[copy * one.positions.size() + i], one.positions[i] + offset);
        for (size_t t = 0; t < one.indices.size(); ++t)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(many.indices[copy * one.indices.size() + t][c], one.indices[t][c] + copy * one.positions.size());
    }
    // The default: teapots, 4 x 3.
    EXPECT_EQ(make("instances").triangle_count(), 12 * make("teapot").triangle_count());
}

TEST(BuiltinScenes, InstancesNameWhatIsWrongWithTheirMesh) {
    auto missing = make_builtin("instances?mesh=/no/such/file.obj");
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error(), "builtin:instances?mesh=/no/such/file.obj: /no/such/file.obj: no such file");
    auto nested = make_builtin("instances?mesh=builtin:instances");
    ASSERT_FALSE(nested);
    expect_contains(nested.error(), "cannot be or contain another builtin:instances");
    auto empty = make_builtin("instances?mesh=");
    ASSERT_FALSE(empty);
    expect_contains(empty.error(), "parameter 'mesh' is empty");
    auto wide = make_builtin("instances?nx=65");
    ASSERT_FALSE(wide);
    expect_contains(wide.error(), "nx=65 is out of range");
}


// --time sets a moving scene's t (adding it or replacing it, never a nested scene's),
// and refuses a scene without one.
TEST(BuiltinScenes, SceneAtTimeSetsTheTimeOfAMovingScene) {
    EXPECT_EQ(*scene_at_time("builtin:moving", 0.5), "builtin:moving?t=0.5");
    EXPECT_EQ(*scene_at_time("builtin:moving?", 0.25), "builtin:moving?t=0.25");
    EXPECT_EQ(*scene_at_time("builtin:moving?n=4", 2), "builtin:moving?n=4&t=2");
    EXPECT_EQ(*scene_at_time("builtin:moving?t=0.1&n=4", -0.75), "builtin:moving?t=-0.75&n=4");
    EXPECT_EQ(*scene_at_time("builtin:wave?mesh=builtin:moving?t=0.3&height=0.2", 0.1),
              "builtin:wave?mesh=builtin:moving?t=0.3&height=0.2&t=0.1");
    EXPECT_EQ(*scene_at_time("builtin:moving", 0.1), "builtin:moving?t=0.1");  // the shortest form that reads back
    for (const char* still : {"builtin:teapot", "bunny.obj", "builtin:instances?mesh=builtin:moving", ""}) {
        const auto at = scene_at_time(still, 0.5);
        ASSERT_FALSE(at.ok()) << still;
        expect_contains(at.error(), "builtin:moving, builtin:wave");
    }
    EXPECT_FALSE(scene_at_time("builtin:moving", std::numeric_limits<double>::infinity()).ok());
    // The scene at a time is the scene with that t.
    const Mesh a = make("moving?n=3&t=0.4"), b = *load_scene(*scene_at_time("builtin:moving?n=3", 0.4));
    EXPECT_EQ(a.positions, b.positions);
}

// Scenes made from scenes nest a few levels at most (a source nesting thousands deep
// is refused, not a crash), and instances never copy copies, even through a wave.
TEST(BuiltinScenes, ScenesMadeFromScenesNestAFewLevelsAtMost) {
    EXPECT_TRUE(load_scene("builtin:wave?mesh=builtin:wave?mesh=builtin:cube").ok());
    std::string deep = "builtin:cube";
    for (int i = 0; i < 7000; ++i) deep = "builtin:wave?mesh=" + deep;
    const auto refused = load_scene(deep);
    ASSERT_FALSE(refused.ok());
    expect_contains(refused.error(), "nest at most");
    EXPECT_LT(refused.error().size(), 2000u);
    const auto copies = load_scene("builtin:instances?mesh=builtin:wave?mesh=builtin:instances?mesh=builtin:cube");
    ASSERT_FALSE(copies.ok());
    expect_contains(copies.error(), "another builtin:instances");
}

// The window's Time slider reads a moving scene's t back from its source.
TEST(BuiltinScenes, SceneTimeReadsTheTimeBack) {
    EXPECT_EQ(scene_time("builtin:moving"), 0.0);
    EXPECT_EQ(scene_time("builtin:moving?n=4&t=0.375"), 0.375);
    EXPECT_EQ(scene_time("builtin:wave?mesh=builtin:moving?t=0.3&height=0.2"), 0.0);  // the nested scene's t is not its own
    EXPECT_EQ(scene_time(*scene_at_time("builtin:wave?mesh=builtin:sphere", 0.1)), 0.1);
    EXPECT_EQ(scene_time("builtin:teapot"), std::nullopt);
    EXPECT_EQ(scene_time("bunny.obj"), std::nullopt);
    EXPECT_EQ(scene_time("builtin:moving?t=soon"), std::nullopt);
}

TEST(BuiltinScenes, TheMirrorCornellBoxIsTheCornellBoxWithItsTallBlockAMirror) {
    const Mesh plain = make("cornell"), mirrored = make("cornell-mirror");
    EXPECT_EQ(plain.positions, mirrored.positions);
    EXPECT_EQ(plain.indices, mirrored.indices);
    EXPECT_TRUE(plain.mirror.empty());
    ASSERT_EQ(mirrored.mirror.size(), mirrored.triangle_count());
    // The tall block (the last 10 triangles) and nothing else; its top is the highest block face.
    for (size_t t = 0; t < mirrored.triangle_count(); ++t) EXPECT_EQ(mirrored.mirror[t] != 0, t >= 22) << t;
    float top = 0;
    for (size_t t = 22; t < 32; ++t)
        for (int c = 0; c < 3; ++c) top = std::max(top, mirrored.vertex(t, c).y);
    EXPECT_FLOAT_EQ(top, 3.3f);
}
