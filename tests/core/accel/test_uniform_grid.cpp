// The uniform grid: exact against brute force in every configuration, honest
// stats, and references exactly where the box / separating-axis test says.
#include <gtest/gtest.h>

#include "accel/space_partition_support.h"
#include "core/accel/uniform_grid.h"
#include "core/geometry/triangle_box.h"

using namespace accelviz;
using namespace accelviz::test;

namespace {

UniformGrid build(const Mesh& mesh, GridConfig config) {
    auto grid = build_uniform_grid(mesh, config);
    if (!grid.ok()) throw std::runtime_error(grid.error());
    return std::move(*grid);
}

/// Box/exact insertion × mailbox on/off, plus a coarse and a fine density.
std::vector<std::pair<std::string, GridConfig>> configs() {
    std::vector<std::pair<std::string, GridConfig>> out;
    for (GridInsert insert : {GridInsert::Box, GridInsert::Exact})
        for (bool mailbox : {true, false}) {
            GridConfig c;
            c.insert = insert;
            c.mailbox = mailbox;
            out.push_back({std::string("insert=") + std::string(to_string(insert)) + " mailbox=" + (mailbox ? "on" : "off"), c});
        }
    GridConfig coarse;
    coarse.density = 0.5f;
    out.push_back({"density=0.5", coarse});
    GridConfig fine;
    fine.density = 200.0f;
    fine.insert = GridInsert::Exact;
    out.push_back({"density=200 exact", fine});
    return out;
}

void check_scene(const std::string& source) {
    const SceneCase& scene = scene_case(source);
    for (const auto& [label, config] : configs()) {
        const UniformGrid grid = build(scene.mesh, config);
        expect_exact(grid, scene, "grid " + label);
        expect_trace_agrees(grid, scene, 97, "grid " + label);
    }
}

}  // namespace

TEST(UniformGrid, ExactOnStadium) { check_scene("builtin:stadium"); }
TEST(UniformGrid, SlowExactOnSameBox) { check_scene("builtin:same-box"); }
TEST(UniformGrid, ExactOnSameCentroid) { check_scene("builtin:same-centroid"); }
TEST(UniformGrid, ExactOnSoup) { check_scene("builtin:soup?n=2000&seed=3"); }
TEST(UniformGrid, ExactOnEmptyScene) { check_scene("builtin:empty"); }
TEST(UniformGrid, ExactOnSingleTriangle) { check_scene("builtin:single"); }
TEST(UniformGrid, ExactOnCornellBox) { check_scene("builtin:cornell"); }
TEST(UniformGrid, SlowExactOnBunny) {
    if (!shared_asset_exists("bunny.obj")) GTEST_SKIP() << "bunny.obj not found";
    check_scene("bunny");
}

TEST(UniformGrid, ResolutionFollowsTheLectureRule) {
    const SceneCase& scene = scene_case("builtin:soup?n=2000&seed=3", 10);
    const UniformGrid grid = build(scene.mesh, GridConfig{});
    const auto& s = grid.build_stats;
    EXPECT_EQ(s.requested_cells, 27u * 2000u);
    // Cubic-ish cells: within a factor 1.5 of the rule, and no note (no cap applied).
    EXPECT_GT(double(s.cells), 27.0 * 2000 / 1.5);
    EXPECT_LT(double(s.cells), 27.0 * 2000 * 1.5);
    EXPECT_TRUE(s.notes.empty());
    EXPECT_EQ(s.cells, uint64_t(s.cells_per_axis[0]) * s.cells_per_axis[1] * s.cells_per_axis[2]);
    EXPECT_EQ(grid.cell_start.back(), s.references);
}

TEST(UniformGrid, FlatSceneGetsOneCellAcrossItsFlatAxis) {
    Mesh m;
    for (int i = 0; i < 100; ++i) m.add_triangle({float(i), 0, 0}, {float(i) + 1, 0, 0}, {float(i), 5, 0});
    const UniformGrid grid = build(m, GridConfig{});
    EXPECT_EQ(grid.res[2], 1);
    EXPECT_GT(grid.res[0], 1);
}

TEST(UniformGrid, AThinAxisDoesNotInflateTheOthers) {
    // From the fuzzer: a scene 2e12 long, 3 deep and 1e-7 high (with 5 triangles,
    // 135 cells by the rule) got 1024 x 1 x 1024 cells, 4 million references.
    Mesh m;
    m.add_triangle({-1e12f, 0, 0}, {1e12f, 0, 0}, {0, 1e-7f, 3});
    m.add_triangle({0, 0, 0}, {1, 0, 0}, {0, 1e-7f, 1});
    const UniformGrid grid = build(m, GridConfig{});
    EXPECT_EQ(grid.build_stats.requested_cells, 54u);
    EXPECT_LE(grid.build_stats.cells, 54u) << grid.res[0] << " x " << grid.res[1] << " x " << grid.res[2];
    EXPECT_EQ(grid.res[1], 1);
    EXPECT_EQ(grid.res[2], 1);
    EXPECT_TRUE(grid.build_stats.notes.empty());
}

TEST(UniformGrid, CapsAreReportedNotHidden) {
    const SceneCase& scene = scene_case("builtin:soup?n=2000&seed=3", 10);
    GridConfig c;
    c.max_cells_per_axis = 8;
    const UniformGrid capped = build(scene.mesh, c);
    EXPECT_LE(capped.res[0], 8);
    ASSERT_FALSE(capped.build_stats.notes.empty());
    EXPECT_NE(capped.build_stats.notes[0].find("capped"), std::string::npos);
    GridConfig t;
    t.max_cells = 1000;
    const UniformGrid total = build(scene.mesh, t);
    EXPECT_LE(total.build_stats.cells, 1000u);
    ASSERT_FALSE(total.build_stats.notes.empty());
    EXPECT_NE(total.build_stats.notes.back().find("lecture's rule"), std::string::npos);
}

TEST(UniformGrid, ReferencesAreExactlyWhereTheOverlapTestSays) {
    const SceneCase& scene = scene_case("builtin:soup?n=300&seed=5", 10);
    for (GridInsert insert : {GridInsert::Box, GridInsert::Exact}) {
        GridConfig c;
        c.insert = insert;
        const UniformGrid g = build(scene.mesh, c);
        const float pad = g.build_stats.padding;
        size_t mismatches = 0;
        for (int k = 0; k < g.res[2]; ++k)
            for (int j = 0; j < g.res[1]; ++j)
                for (int i = 0; i < g.res[0]; ++i) {
                    const uint32_t id = g.cell_id(i, j, k);
                    const Aabb cell = g.cell_bounds(i, j, k);
                    std::vector<char> in_cell(scene.mesh.triangle_count(), 0);
                    for (uint32_t r = g.cell_start[id]; r < g.cell_start[id + 1]; ++r) in_cell[g.tri_ids[r]] = 1;
                    for (uint32_t t = 0; t < scene.mesh.triangle_count(); ++t) {
                        // The build's two tests: padded triangle box against the cell, then
                        // (exact) the triangle against the padded cell.
                        const Aabb tb = padded(scene.mesh.triangle_bounds(t), pad);
                        const bool box_overlap = !intersection(tb, cell).empty();
                        const bool expected = insert == GridInsert::Box
                                                  ? box_overlap
                                                  : box_overlap && triangle_overlaps_box(scene.mesh.vertex(t, 0),
                                                                                         scene.mesh.vertex(t, 1),
                                                                                         scene.mesh.vertex(t, 2),
                                                                                         padded(cell, pad));
                        if (bool(in_cell[t]) != expected) ++mismatches;
                    }
                }
        EXPECT_EQ(mismatches, 0u) << to_string(insert);
    }
}

TEST(UniformGrid, ExactInsertionStoresFewerReferences) {
    const SceneCase& scene = scene_case("builtin:soup?n=2000&seed=3", 10);
    GridConfig box, exact;
    exact.insert = GridInsert::Exact;
    EXPECT_LT(build(scene.mesh, exact).build_stats.references, build(scene.mesh, box).build_stats.references);
}

TEST(UniformGrid, MailboxSavesTestsWithoutChangingAnswers) {
    const SceneCase& scene = scene_case("builtin:soup?n=2000&seed=3", 2000);
    GridConfig on, off;
    off.mailbox = false;
    const UniformGrid g_on = build(scene.mesh, on), g_off = build(scene.mesh, off);
    Counters c_on, c_off;
    for (const Ray& r : scene.rays) {
        CountingObserver a, b;
        EXPECT_TRUE(same_hit(g_on.intersect_closest(r, a), g_off.intersect_closest(r, b)));
        c_on += a.counters;
        c_off += b.counters;
    }
    EXPECT_GT(c_on.mailbox_skips, 0u);
    EXPECT_EQ(c_off.mailbox_skips, 0u);
    // Every skip is a test saved.
    EXPECT_EQ(c_on.triangle_tests + c_on.mailbox_skips, c_off.triangle_tests);
}

TEST(UniformGrid, WalkVisitsCellsInOrderAlongTheRay) {
    const SceneCase& scene = scene_case("builtin:soup?n=2000&seed=3", 500);
    const UniformGrid g = build(scene.mesh, GridConfig{});
    for (const Ray& r : scene.rays) {
        RecordingObserver rec;
        g.intersect_closest(r, rec);
        float last_exit = -kInfinity;
        int cells = 0;
        for (const TraversalEvent& e : rec.events)
            if (e.kind == EventKind::EnterCell) {
                if (cells++ > 0) {
                    EXPECT_EQ(e.t_enter, last_exit);  // each cell starts where the last ended
                }
                EXPECT_LE(e.t_enter, e.t_exit);
                last_exit = e.t_exit;
            }
        EXPECT_LE(cells, g.res[0] + g.res[1] + g.res[2]);
    }
}

TEST(UniformGrid, HitBeyondTheCellIsDeferredThenAccepted) {
    // A long slanted triangle first tested in an early cell, hit far away; the
    // walk must remember it (HitOutsideCell) and accept it in its own cell.
    Mesh m;
    m.add_triangle({0, -2, -0.8f}, {0, 2, -0.8f}, {10, 0, 0.2f});  // the ray meets it at x = 8
    for (int i = 0; i < 30; ++i) m.add_triangle({float(i) * 0.3f, 3, 3}, {float(i) * 0.3f + 0.1f, 3, 3}, {float(i) * 0.3f, 3.1f, 3});
    const UniformGrid g = build(m, GridConfig{});
    RecordingObserver rec;
    const Hit h = g.intersect_closest(Ray{{-1, 0, 0}, {1, 0, 0}}, rec);
    ASSERT_TRUE(h.found());
    EXPECT_EQ(h.tri, 0u);
    bool deferred = false, accepted_after = false;
    for (const auto& e : rec.events) {
        if (e.kind == EventKind::HitOutsideCell && e.tri == 0) deferred = true;
        if (deferred && e.kind == EventKind::NewClosest && e.tri == 0) accepted_after = true;
    }
    EXPECT_TRUE(deferred);
    EXPECT_TRUE(accepted_after);
}

TEST(UniformGrid, DegenerateRaysAreAnsweredLikeBruteForce) {
    for (const char* source : {"builtin:soup?n=2000&seed=3", "builtin:single", "builtin:empty", "builtin:cornell"}) {
        const SceneCase& scene = scene_case(source, 10);
        for (const auto& [label, config] : configs())
            expect_degenerate_rays_answered(build(scene.mesh, config), scene.mesh, std::string("grid ") + label + " on " + source);
    }
}

TEST(UniformGrid, OriginsOnCellBoundaries) {
    for (const char* source : {"builtin:soup?n=2000&seed=3", "builtin:cornell", "builtin:stadium"}) {
        const SceneCase& scene = scene_case(source, 10);
        for (const auto& [label, config] : configs()) {
            const UniformGrid g = build(scene.mesh, config);
            const SceneCase on_planes = rays_on_planes(scene.mesh, g.planes, 20000, 11);
            expect_exact(g, on_planes, "grid " + label + " origins on cell planes");
        }
    }
}
