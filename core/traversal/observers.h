#pragma once
/// Observers of a traversal. Every traversal is one template
///   template <class Observer> Hit intersect_closest(..., Observer& obs)
/// that calls obs.on(TraversalEvent{...}) at each step. With NoObserver the call
/// is an empty inline function and the optimizer removes the event entirely, so
/// the fast path and the instrumented path are the same code.

#include <type_traits>
#include <vector>

#include "core/traversal/events.h"

namespace accelviz {

/// What a traversal looks for: the closest hit (camera and reflection rays), or any
/// hit in [t_min, t_max] (shadow rays: one occluder is enough, so the walk stops
/// there; the lecture's "哪些光源可见"). One switch of every structure's walk.
enum class StopAt {
    ClosestHit,  ///< keep the closest hit; skip what starts beyond it
    AnyHit,      ///< stop at the first hit
};

/// The fast path: sees nothing, costs nothing.
struct NoObserver {
    void on(const TraversalEvent&) {}
};

/// Whether a traversal's events are looked at (by every observer but NoObserver).
template <class Observer>
inline constexpr bool kObserverWatches = !std::is_same_v<Observer, NoObserver>;

/// A ray query's last event, Done, with its answer `best` (Hit{}: no hit), and the
/// answer: how every structure's walk ends.
template <class Observer>
Hit report_done(const Hit& best, Observer& obs) {
    obs.on({.kind = EventKind::Done, .hit = best.found(), .tri = best.tri, .t = best.t, .u = best.u, .v = best.v});
    return best;
}

/// A value a traversal carries only to report it in events (a node's id, an exit
/// distance). When nobody watches (kKept false) it is an empty type: as a
/// [[no_unique_address]] member it takes no room, and it reads as T{}. So the walk
/// itself must never depend on it (the brute-force tests run the unwatched walk).
template <class T, bool kKept>
struct KeptForEvents {
    T value;
    KeptForEvents() = default;
    KeptForEvents(T v) : value(v) {}
    operator T() const { return value; }
};
template <class T>
struct KeptForEvents<T, false> {
    KeptForEvents() = default;
    KeptForEvents(T) {}
    operator T() const { return T{}; }
};

/// Work done by one ray (or summed over many): what heat maps and bench show.
struct Counters {
    uint64_t nodes_visited = 0;   ///< VisitNode + EnterCell
    uint64_t box_tests = 0;       ///< BoxTest
    uint64_t triangle_tests = 0;  ///< TriangleTest
    uint64_t mailbox_skips = 0;   ///< MailboxSkip
    uint64_t hits_outside_cell = 0;
    uint64_t culls = 0;

    void add(const TraversalEvent& e) {
        switch (e.kind) {
            case EventKind::VisitNode:
            case EventKind::EnterCell: ++nodes_visited; break;
            case EventKind::BoxTest: ++box_tests; break;
            case EventKind::TriangleTest: ++triangle_tests; break;
            case EventKind::MailboxSkip: ++mailbox_skips; break;
            case EventKind::HitOutsideCell: ++hits_outside_cell; break;
            case EventKind::Cull: ++culls; break;
            default: break;
        }
    }
    Counters& operator+=(const Counters& o) {
        nodes_visited += o.nodes_visited; box_tests += o.box_tests;
        triangle_tests += o.triangle_tests; mailbox_skips += o.mailbox_skips;
        hits_outside_cell += o.hits_outside_cell; culls += o.culls;
        return *this;
    }
    bool operator==(const Counters&) const = default;
};

/// Counts work: heat maps and bench.
struct CountingObserver {
    Counters counters;
    void on(const TraversalEvent& e) { counters.add(e); }
};

/// Records every event: `trace --json` and the stepper.
struct RecordingObserver {
    std::vector<TraversalEvent> events;
    void on(const TraversalEvent& e) { events.push_back(e); }
    Counters counters() const {
        Counters c;
        for (const auto& e : events) c.add(e);
        return c;
    }
};

}  // namespace accelviz
