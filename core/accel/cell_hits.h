#pragma once
/// What the space-partitioning structures (uniform grid, KD tree, octree, BSP tree) share
/// at traversal time: the lecture's rule for a triangle that lies in several
/// cells (slide "KD 树划分的挑战": 要求交点必须在相同区域内; 已经访问过的图像基元
/// 可以缓存下来), and the mailbox that caches the triangles already tested.
///
/// The walk visits cells front to back. In each cell it tests the cell's
/// triangles; a hit counts only if its t lies inside the current cell's
/// [t_in, t_out]. A hit beyond t_out is remembered (HitOutsideCell) and accepted
/// (NewClosest) when the walk enters the cell that contains its t; the walk
/// stops after the first cell whose t_out is strictly beyond the closest hit
/// (so an equal-t hit with a smaller id in the next cell is still found).
///
/// Exactness: the remembered hit is the closest (by is_closer) over every
/// triangle tested so far, and triangles are tested with t_max = that hit's t
/// (inclusive), exactly as BruteForce does, so the answer is brute force's as
/// soon as every triangle that could beat it has been tested; the stopping
/// rule and the references' safety margin (reference_padding) make sure of that.

#include <cstdint>
#include <vector>

#include "core/geometry/triangle_lanes.h"
#include "core/traversal/observers.h"

namespace accelviz {

/// A per-ray mailbox: the set of triangle ids this ray has tested. It lives with
/// the ray (on its stack), so a built structure stays immutable and any number of
/// threads can trace through it: no per-triangle "last ray" field in shared
/// memory. Exact, in two stages:
///   - a 64-slot open-addressing hash table (linear probing) for the first 32
///     ids: 256 bytes to clear per ray, one or two probes per lookup;
///   - past 32 ids, a bitset over all triangle ids, allocated then: a ray that
///     has tested that many triangles (a crowded grid cell) pays its clearing
///     back quickly, and lookups stay O(1) however many it tests.
class Mailbox {
public:
    static constexpr uint32_t kSlots = 64;      ///< power of two
    static constexpr uint32_t kMaxInTable = 32;  ///< load factor 1/2, then the bitset

    explicit Mailbox(uint32_t triangle_count) : triangle_count_(triangle_count) {}

    /// True if `tri` was tested already (skip it); otherwise records it.
    bool seen(uint32_t tri) {
        if (!bits_.empty()) return test_and_set(tri);
        if (!cleared_) {  // cleared on first use: rays that test nothing pay nothing
            for (uint32_t& id : slots_) id = Hit::kNoHit;
            cleared_ = true;
        }
        uint32_t slot = (tri * 2654435761u) >> 26;  // Knuth's multiplicative hash, top 6 bits
        while (slots_[slot] != Hit::kNoHit) {
            if (slots_[slot] == tri) return true;
            slot = (slot + 1) & (kSlots - 1);
        }
        if (count_ < kMaxInTable) {
            slots_[slot] = tri;
            ++count_;
            return false;
        }
        // The table is full enough: move to the bitset.
        bits_.assign((size_t(triangle_count_) + 63) / 64, 0);
        for (uint32_t id : slots_)
            if (id != Hit::kNoHit) test_and_set(id);
        return test_and_set(tri);
    }

private:
    bool test_and_set(uint32_t tri) {
        uint64_t& word = bits_[tri >> 6];
        const uint64_t bit = uint64_t(1) << (tri & 63);
        const bool was = (word & bit) != 0;
        word |= bit;
        return was;
    }

    static_assert(kSlots == 64, "the hash keeps the top 6 bits");
    uint32_t slots_[kSlots];
    bool cleared_ = false;
    uint32_t count_ = 0;
    uint32_t triangle_count_;
    std::vector<uint64_t> bits_;  ///< empty until the table holds kMaxInTable ids
};

/// The closest-hit bookkeeping of one ray's walk through cells, testing triangles
/// with test kTest (TriangleTester). With kStop = AnyHit (shadow rays) the in-cell
/// rule does not apply: a hit anywhere in [t_min, t_max] blocks the segment, so the
/// first hit found ends the walk, in whichever cell it was tested.
template <TriangleTestKind kTest, StopAt kStop = StopAt::ClosestHit>
class CellHits {
public:
    /// `strict_cell` false is the naive rule (teaching switch): any hit found in a
    /// cell is accepted at once and ends the walk after that cell, which gives
    /// wrong answers when a triangle's hit lies beyond the cell it was tested in.
    /// `triangle_count`: ids are below it (the mailbox's bitset size).
    /// `triangles`, `corners`: the structure's arrays, as TriangleTester reads them;
    /// `pre`: RayPrecomp(ray), which the walk made for its root box.
    /// Made only once the ray has entered the structure's box: a ray that misses it
    /// (most of a wide view) pays for none of this set-up (missed()).
    /// Always inlined: the trees' walks are faster so; the grid's a little slower (its
    /// loop's registers are allocated differently). Figures in docs/performance.md.
    [[gnu::always_inline]] CellHits(const Ray& ray, const RayPrecomp& pre, const TriangleArray& triangles,
                                    const CornerArray& corners, bool use_mailbox, bool strict_cell,
                                    uint32_t triangle_count)
        : test_ray_(ray), tester_(ray, pre, triangles, corners), use_mailbox_(use_mailbox),
          strict_(strict_cell), mailbox_(triangle_count) {}

    /// The answer, and done()'s event, for a ray that enters no cell (an empty
    /// structure, or a ray that misses its box): no hit.
    template <class Observer>
    static Hit missed(Observer& obs) {
        return report_done(Hit{}, obs);
    }

    /// The walk enters a cell spanning [t_in, t_out] along the ray. A hit
    /// remembered from an earlier cell whose t lies in this cell is accepted now.
    template <class Observer>
    void enter(float t_out, Observer& obs) {
        t_out_ = t_out;
        if (pending_ && !(best_.t > t_out)) {
            pending_ = false;
            obs.on({.kind = EventKind::NewClosest, .tri = best_.tri, .t = best_.t, .u = best_.u, .v = best_.v});
        }
    }

    /// Tests one triangle referenced by the current cell: triangle k of the
    /// structure's arrays, whose id is `id`.
    template <class Observer>
    void test(size_t k, uint32_t id, Observer& obs) {
        if (use_mailbox_ && mailbox_.seen(id)) {
            obs.on({.kind = EventKind::MailboxSkip, .tri = id});
            return;
        }
        take(tester_.test(k, test_ray_), id, obs);
    }

    /// The same for a triangle of a leaf kept as lanes (for_each_lane_test,
    /// triangle_lanes.h), whose id is `id`: result() is its TriangleTest, test()'s bit
    /// for bit, computed only if the mailbox has not seen the triangle.
    template <class LaneResult, class Observer>
    void test_lane(const LaneResult& result, uint32_t id, Observer& obs) {
        if (use_mailbox_ && mailbox_.seen(id)) {
            obs.on({.kind = EventKind::MailboxSkip, .tri = id});
            return;
        }
        take(result(), id, obs);
    }

    /// Whether every triangle must be looked at (the mailbox records each), or only
    /// the candidates of a lane test (the others cannot hit).
    bool uses_mailbox() const { return use_mailbox_; }
    /// The ray the triangles are tested with (t_max: the closest hit so far).
    const Ray& test_ray() const { return test_ray_; }
    /// The box test's view of the ray, for the triangle test's own-box rule.
    const BoxTestRay& box_ray() const { return tester_.box_ray(); }

    /// After the current cell: may the walk stop? Strict: yes once the closest
    /// hit lies strictly before the cell's end (every later cell starts at or
    /// after t_out). Naive: as soon as any hit was found.
    bool can_stop() const {
        if (!best_.found()) return false;
        if constexpr (kStop == StopAt::AnyHit) return true;
        return strict_ ? best_.t < t_out_ : true;
    }

    /// Any-hit: a hit was found, so the rest of the cell's triangles need no test.
    bool found_any() const { return kStop == StopAt::AnyHit && best_.found(); }

    /// The closest hit so far (accepted or still pending; any-hit: the hit found).
    const Hit& best() const { return best_; }

    /// The final answer. A hit still pending here (the walk ran out of cells
    /// first, which only rounding at the structure's boundary can cause) is
    /// still the closest over all triangles tested, so it is the answer.
    template <class Observer>
    Hit done(Observer& obs) const {
        return report_done(best_, obs);
    }

private:
    /// A triangle's test result: the closest-hit bookkeeping and its events.
    template <class Observer>
    void take(const TriangleTest& test, uint32_t id, Observer& obs) {
        obs.on({.kind = EventKind::TriangleTest, .hit = test.hit, .tri = id, .t = test.t, .u = test.u, .v = test.v});
        if constexpr (kStop == StopAt::AnyHit) {
            if (test.hit) best_ = {id, test.t, test.u, test.v};
            return;
        }
        if (!test.hit || !is_closer(test.t, id, best_)) return;
        best_ = {id, test.t, test.u, test.v};
        test_ray_.t_max = test.t;  // later triangles must be at least this close (inclusive, as BruteForce)
        if (strict_ && test.t > t_out_) {
            pending_ = true;
            obs.on({.kind = EventKind::HitOutsideCell, .tri = id, .t_exit = t_out_, .t = test.t, .u = test.u,
                    .v = test.v});
        } else {
            pending_ = false;
            obs.on({.kind = EventKind::NewClosest, .tri = id, .t = test.t, .u = test.u, .v = test.v});
        }
    }

    Ray test_ray_;  ///< the ray with t_max = closest hit so far
    TriangleTester<kTest> tester_;
    Hit best_;
    float t_out_ = kInfinity;
    bool pending_ = false;  ///< best_ lies beyond the cells walked so far
    bool use_mailbox_;
    bool strict_;
    Mailbox mailbox_;
};

/// The two queries of every structure that walks cells (grid, KD tree, octree, BSP
/// tree), answered by its one walk `front_to_back<kTest, kStop>` (CRTP): the closest
/// hit in [ray.t_min, ray.t_max], and any hit there (shadow rays: the same walk, ended
/// by the first hit wherever it lies, CellHits' any-hit mode). The triangle test is
/// chosen once per ray and compiled into the walk.
template <class Derived>
struct CellQueries {
    template <class Observer>
    Hit intersect_closest(const Ray& ray, Observer& obs) const {
        return walk<StopAt::ClosestHit>(ray, obs);
    }
    template <class Observer>
    bool intersect_any(const Ray& ray, Observer& obs) const {
        return walk<StopAt::AnyHit>(ray, obs).found();
    }
    bool intersect_any(const Ray& ray) const {
        NoObserver none;
        return intersect_any(ray, none);
    }

private:
    template <StopAt kStop, class Observer>
    Hit walk(const Ray& ray, Observer& obs) const {
        const Derived& self = static_cast<const Derived&>(*this);
        return self.triangle_test == TriangleTestKind::Watertight
                   ? self.template front_to_back<TriangleTestKind::Watertight, kStop>(ray, obs)
                   : self.template front_to_back<TriangleTestKind::MollerTrumbore, kStop>(ray, obs);
    }
};

}  // namespace accelviz
