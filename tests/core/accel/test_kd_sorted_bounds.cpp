// The KD build's sorted bounds: a child's six lists made from its parent's (kept
// bounds filtered through, the cut references' new bounds merged in) are the lists a
// sort of the child's references gives, value for value, each bound with its owner,
// down many levels of random planes, with both clipping rules, on triangles as thin as
// the references' padding (boxes a split keeps whole on both sides) and on ties.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstring>

#include "core/accel/kd_sorted_bounds.h"
#include "core/geometry/scene.h"
#include "core/geometry/triangle_box.h"
#include "core/util/random.h"

namespace accelviz {
namespace {

/// `bounds` are `refs`' lists: each sorted, each value the bound of its owner bit for
/// bit, every reference once a list.
void expect_lists_of(const SpatialRefs& refs, const SortedBounds& bounds) {
    ASSERT_EQ(bounds.n, refs.size());
    const SortedBounds fresh = sort_bounds(refs);
    for (int k = 0; k < 6; ++k) {
        const std::span<const float> list = bounds.list(k), expected = fresh.list(k);
        const uint32_t* owners = bounds.owners.data() + size_t(k) * bounds.stride();
        ASSERT_TRUE(std::is_sorted(list.begin(), list.end())) << "list " << k;
        std::vector<bool> seen(refs.size(), false);
        for (size_t i = 0; i < refs.size(); ++i) {
            ASSERT_EQ(list[i], expected[i]) << "list " << k << " position " << i;
            ASSERT_LT(owners[i], refs.size());
            ASSERT_FALSE(seen[owners[i]]) << "list " << k << ": reference " << owners[i] << " twice";
            seen[owners[i]] = true;
            ASSERT_EQ(std::bit_cast<uint32_t>(list[i]), std::bit_cast<uint32_t>(SortedBounds::bound(refs[owners[i]], k)))
                << "list " << k << " position " << i;
        }
    }
}

/// Splits `refs` (the node `cell`) at random planes through a reference's bound or at
/// random, `levels` deep, checking every child's lists made from its parent's.
void check_down(const SpatialRefs& refs, const SortedBounds& bounds, const Aabb& cell, const CornerTriples& triangles,
                float pad, PartRule rule, Rng& rng, int levels, size_t& checked) {
    if (levels == 0 || refs.size() < 2) return;
    const int a = int(rng.next_u64() % 3);
    float s = refs[rng.next_u64() % refs.size()].box.hi[a];  // on a bound: the SAH's candidates
    if (rng.next_u64() % 3 == 0) s = rng.uniform(cell.lo[a], cell.hi[a]);
    if (!(s > cell.lo[a] && s < cell.hi[a])) s = 0.5f * (cell.lo[a] + cell.hi[a]);
    std::array<SpatialRefs, 2> children;
    Vec3 planes;
    planes[a] = s;
    ChildRefs parts;
    for (const SpatialRef& r : refs) {
        split_reference(r, triangles, cell, planes, 1u << a, pad, rule, parts);
        for (int k = 0; k < parts.count; ++k) children[parts.child[k] == 0 ? 0 : 1].push_back(parts.ref[k]);
    }
    const std::array<bool, 2> wanted = {rng.next_u64() % 4 != 0, rng.next_u64() % 4 != 0};
    const std::array<SortedBounds, 2> made = children_bounds(refs, bounds, {&children[0], &children[1]}, wanted);
    for (size_t side = 0; side < 2; ++side) {
        if (!wanted[side]) {
            EXPECT_FALSE(made[side].made());
            continue;
        }
        expect_lists_of(children[side], made[side]);
        if (::testing::Test::HasFatalFailure()) return;
        ++checked;
        Aabb child_cell = cell;
        (side == 0 ? child_cell.hi : child_cell.lo)[a] = s;
        check_down(children[side], made[side], child_cell, triangles, pad, rule, rng, levels - 1, checked);
    }
}

void check_mesh(const Mesh& mesh, uint64_t seed) {
    const Aabb box = mesh.bounds();
    const float pad = reference_padding(box);
    const SpatialRefs root = root_references(mesh, pad);
    const SortedBounds root_bounds = sort_bounds(root);
    expect_lists_of(root, root_bounds);
    const CornerTriples triangles = corner_triples(mesh);
    for (PartRule rule : {PartRule::Clipped, PartRule::BoxOverlap}) {
        Rng rng(seed);
        size_t checked = 0;
        for (int round = 0; round < 6; ++round)
            check_down(root, root_bounds, padded(box, pad), triangles, pad, rule, rng, 7, checked);
        EXPECT_GT(checked, 30u);
    }
}

TEST(KdSortedBounds, ChildrensListsAreASortOfTheirReferences) {
    for (const char* source : {"builtin:soup?n=3000&seed=5", "builtin:teapot", "builtin:same-box", "builtin:cornell"}) {
        SCOPED_TRACE(source);
        auto mesh = load_scene(source, MeshCache::Skip);
        ASSERT_TRUE(mesh.ok());
        check_mesh(*mesh, 21);
    }
}

TEST(KdSortedBounds, ThinTrianglesAndSharedCoordinates) {
    // Triangles thinner than the padding (a split can leave such a box whole in both
    // children) and coordinates on a coarse lattice (many equal bounds, both zeros).
    Rng rng(9);
    Mesh mesh;
    for (int t = 0; t < 4000; ++t) {
        const uint32_t first = uint32_t(mesh.positions.size());
        Vec3 at{float(int(rng.next_u64() % 9) - 4), float(int(rng.next_u64() % 9) - 4),
                float(int(rng.next_u64() % 9) - 4)};
        if (t % 3 == 0) at = at * -1.0f;  // -0 where the lattice has 0
        const float size = t % 2 ? 1e-7f : 1.0f;
        for (int c = 0; c < 3; ++c)
            mesh.positions.push_back(at + Vec3{size * float(rng.next_u64() % 3), size * float(rng.next_u64() % 3),
                                               size * float(rng.next_u64() % 3)});
        mesh.indices.push_back({first, first + 1, first + 2});
    }
    check_mesh(mesh, 33);
}

TEST(KdSortedBounds, ChildrenNotMadeFromTheParentInOrderAreSortedFromScratch) {
    // A child list that is not the parent's references in order (here reversed), or a
    // parent without lists: the lists are still the child's, sorted from scratch.
    auto mesh = load_scene("builtin:soup?n=500&seed=2", MeshCache::Skip);
    ASSERT_TRUE(mesh.ok());
    const Aabb box = mesh->bounds();
    const float pad = reference_padding(box);
    const SpatialRefs root = root_references(*mesh, pad);
    SpatialRefs reversed(root.rbegin(), root.rend()), half(root.begin(), root.begin() + 200);
    const SortedBounds root_bounds = sort_bounds(root);
    const std::array<SortedBounds, 2> made = children_bounds(root, root_bounds, {&reversed, &half}, {true, true});
    expect_lists_of(reversed, made[0]);
    expect_lists_of(half, made[1]);
    const std::array<SortedBounds, 2> without = children_bounds(root, SortedBounds{}, {&reversed, &half}, {true, false});
    expect_lists_of(reversed, without[0]);
    EXPECT_FALSE(without[1].made());
}

}  // namespace
}  // namespace accelviz
