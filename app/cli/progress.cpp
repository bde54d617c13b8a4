#include "app/cli/progress.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace accelviz::cli {
namespace {

std::atomic<bool> progress_lines{true};

std::chrono::milliseconds threshold() {
    if (const char* text = std::getenv("ACCELVIZ_PROGRESS_AFTER_MS"); text && *text)
        return std::chrono::milliseconds(std::strtol(text, nullptr, 10));
    return std::chrono::seconds(2);
}

}  // namespace

void set_progress_lines(bool on) { progress_lines = on; }

StepProgress::StepProgress(std::string command, std::string what)
    : prefix_("accelviz " + command + ": " + what), start_(std::chrono::steady_clock::now()) {
    if (!progress_lines) return;
    const std::chrono::milliseconds after = threshold();
    if (after.count() <= 0) {
        // No wait at all (tests set this): said here, not by a thread that a quick step
        // could end before it runs.
        std::fprintf(stderr, "%s ...\n", prefix_.c_str());
        printed_ = true;
        return;
    }
    watcher_ = std::thread([this, after] {
        std::unique_lock lock(mutex_);
        if (ended_.wait_for(lock, after, [this] { return done_; })) return;
        std::fprintf(stderr, "%s ...\n", prefix_.c_str());
        printed_ = true;
    });
}

StepProgress::~StepProgress() {
    if (watcher_.joinable()) {
        {
            std::lock_guard lock(mutex_);
            done_ = true;
        }
        ended_.notify_all();
        watcher_.join();
    }
    if (printed_) {
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        std::fprintf(stderr, "%s: %.1f s\n", prefix_.c_str(), seconds);
    }
}

}  // namespace accelviz::cli
