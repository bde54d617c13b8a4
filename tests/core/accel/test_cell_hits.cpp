// The per-ray mailbox and the in-cell rule shared by the grid, KD tree and octree.
#include <gtest/gtest.h>

#include "core/accel/cell_hits.h"

using namespace accelviz;

TEST(Mailbox, RemembersEveryIdAcrossTheSwitchToTheBitset) {
    Mailbox box(5000);
    // Ids chosen to collide in the hash table, then many more than the table holds.
    std::vector<uint32_t> ids;
    for (uint32_t i = 0; i < 2000; ++i) ids.push_back((i * 64) % 4999);
    std::vector<char> inserted(5000, 0);
    for (uint32_t id : ids) {
        EXPECT_EQ(box.seen(id), bool(inserted[id])) << id;
        inserted[id] = 1;
    }
    for (uint32_t id = 0; id < 5000; ++id) EXPECT_EQ(box.seen(id), bool(inserted[id])) << id;
}

TEST(CellHits, HitBeyondTheCellIsDeferredUntilItsCell) {
    // One triangle in the plane z = 5; the ray runs along +z.
    const TriangleArray tris{Triangle::from_points({-1, -1, 5}, {1, -1, 5}, {0, 1, 5})};
    const Ray ray{{0, 0, 0}, {0, 0, 1}};
    RecordingObserver rec;
    CellHits<TriangleTestKind::MollerTrumbore> hits(ray, RayPrecomp(ray), tris, {}, /*use_mailbox=*/true, /*strict_cell=*/true, 1);
    hits.enter(2.0f, rec);  // first cell: t in [0, 2]
    hits.test(0, 0, rec);
    EXPECT_FALSE(hits.can_stop());
    EXPECT_EQ(rec.events.back().kind, EventKind::HitOutsideCell);
    hits.enter(4.0f, rec);  // second cell [2, 4]: still before the hit
    hits.test(0, 0, rec);  // mailbox: not tested again
    EXPECT_EQ(rec.events.back().kind, EventKind::MailboxSkip);
    EXPECT_FALSE(hits.can_stop());
    hits.enter(6.0f, rec);  // third cell [4, 6] holds t = 5: accepted on entry
    EXPECT_EQ(rec.events.back().kind, EventKind::NewClosest);
    EXPECT_TRUE(hits.can_stop());
    EXPECT_EQ(hits.done(rec).t, 5.0f);
}

TEST(CellHits, HitExactlyAtTheCellEndKeepsTheWalkGoing) {
    // t == t_out counts in this cell, but the next cell (starting at the same t)
    // may hold a triangle with the same t and a smaller id: do not stop yet.
    const TriangleArray tris{Triangle::from_points({-1, -1, 2}, {1, -1, 2}, {0, 1, 2})};
    const Ray ray{{0, 0, 0}, {0, 0, 1}};
    NoObserver none;
    CellHits<TriangleTestKind::MollerTrumbore> hits(ray, RayPrecomp(ray), tris, {}, true, true, 8);
    hits.enter(2.0f, none);
    hits.test(0, 7, none);
    EXPECT_FALSE(hits.can_stop());
    hits.enter(3.0f, none);
    hits.test(0, 3, none);  // the same triangle as id 3: same t, smaller id
    EXPECT_TRUE(hits.can_stop());
    EXPECT_EQ(hits.best().tri, 3u);
}

TEST(CellHits, NaiveRuleStopsAtTheFirstCellWithAHit) {
    const TriangleArray far{Triangle::from_points({-1, -1, 5}, {1, -1, 5}, {0, 1, 5})};
    const Ray ray{{0, 0, 0}, {0, 0, 1}};
    NoObserver none;
    CellHits<TriangleTestKind::MollerTrumbore> hits(ray, RayPrecomp(ray), far, {}, true, /*strict_cell=*/false, 1);
    hits.enter(2.0f, none);
    hits.test(0, 0, none);
    EXPECT_TRUE(hits.can_stop());  // the lecture's pitfall: it never looks at the cells in between
}
