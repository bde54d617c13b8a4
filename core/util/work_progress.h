#pragma once
/// How far a long load or build has got, and whether anyone still wants it.
///
/// Shared by the thread doing the work and the one watching it (the window's
/// progress bar and Cancel button). The work counts units done out of a total it
/// sets (bytes of a file, triangles placed in leaves, ...); the watcher reads the
/// fraction and may ask the work to stop. Work that sees cancelled() stops at its
/// next check, gives up what it made and returns a WorkProgress::cancelled_error().
/// Every function that takes one accepts a null pointer: no one is watching.

#include <algorithm>
#include <atomic>
#include <cstdint>

#include "core/util/expected.h"

namespace accelviz {

class WorkProgress {
public:
    /// Starts counting a new stage of `total` units (loading, then building). `label`
    /// (a string literal, or null): what the stage does when its caller's own name for
    /// the work does not say it, e.g. "writing the cache copy" inside a load.
    void start_stage(uint64_t total, const char* label = nullptr) {
        if (done_.load(std::memory_order_relaxed) < total_.load(std::memory_order_relaxed))
            left_short_.store(true, std::memory_order_relaxed);
        done_.store(0, std::memory_order_relaxed);
        total_.store(total, std::memory_order_relaxed);
        label_.store(label, std::memory_order_relaxed);
    }
    /// The current stage's label (null when it has none).
    const char* stage_label() const { return label_.load(std::memory_order_relaxed); }
    /// The labelled part of a stage is over (what follows is the caller's own work).
    void clear_stage_label() { label_.store(nullptr, std::memory_order_relaxed); }
    void advance(uint64_t units) { done_.fetch_add(units, std::memory_order_relaxed); }
    /// Done / total of the current stage, in [0, 1]; 0 before a stage has a total.
    double fraction() const {
        const uint64_t total = total_.load(std::memory_order_relaxed);
        if (total == 0) return 0.0;
        return std::min(1.0, double(done_.load(std::memory_order_relaxed)) / double(total));
    }
    /// Whether every stage before the current one counted up to its total before the
    /// next began (work that counts right moves the bar to its end at every stage).
    bool earlier_stages_finished() const { return !left_short_.load(std::memory_order_relaxed); }
    void cancel() { cancelled_.store(true, std::memory_order_relaxed); }
    bool cancelled() const { return cancelled_.load(std::memory_order_relaxed); }

    /// What cancelled work returns.
    static Error cancelled_error() { return Error{"cancelled"}; }

private:
    std::atomic<uint64_t> done_{0};
    std::atomic<uint64_t> total_{0};
    std::atomic<const char*> label_{nullptr};
    std::atomic<bool> cancelled_{false};
    std::atomic<bool> left_short_{false};
};

/// The null-tolerant forms the builders call.
inline bool cancelled(const WorkProgress* progress) { return progress && progress->cancelled(); }
inline void advance(WorkProgress* progress, uint64_t units) {
    if (progress) progress->advance(units);
}
inline void start_stage(WorkProgress* progress, uint64_t total, const char* label = nullptr) {
    if (progress) progress->start_stage(total, label);
}

}  // namespace accelviz
