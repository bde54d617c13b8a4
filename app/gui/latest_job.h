#pragma once
/// One worker thread that runs the newest piece of work handed to it: a request
/// made while another is running replaces any request still waiting, and the
/// result of a request that was superseded is dropped. For work the UI asks for
/// again and again while the user moves (ray casting the current view): only
/// the latest answer matters, and the UI thread never waits for it.

#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>

namespace accelviz {

template <class Result>
class LatestJob {
public:
    LatestJob() : worker_([this] { run(); }) {}
    /// Waits for the running work (if any), then stops the worker.
    ~LatestJob() {
        {
            std::lock_guard lock(mutex_);
            quit_ = true;
            pending_ = nullptr;
        }
        wake_.notify_all();
        worker_.join();
    }
    LatestJob(const LatestJob&) = delete;
    LatestJob& operator=(const LatestJob&) = delete;

    /// Hands over work; replaces work not started yet, supersedes work running.
    void submit(std::function<Result()> work) {
        {
            std::lock_guard lock(mutex_);
            pending_ = std::move(work);
            ++newest_;
            finished_.reset();
        }
        wake_.notify_all();
    }
    /// The newest work's result, once.
    std::optional<Result> take() {
        std::lock_guard lock(mutex_);
        return std::exchange(finished_, std::nullopt);
    }
    bool busy() const {
        std::lock_guard lock(mutex_);
        return pending_ != nullptr || running_;
    }
    bool has_result() const {
        std::lock_guard lock(mutex_);
        return finished_.has_value();
    }
    /// Blocks until the newest work has finished (headless renders, tests).
    void wait() {
        std::unique_lock lock(mutex_);
        done_.wait(lock, [this] { return pending_ == nullptr && !running_; });
    }
    /// Called on the worker when a result is ready (e.g. to wake the window).
    std::function<void()> on_finished;
    /// true: the result of work superseded while it ran is handed out too (until a
    /// newer one finishes), for progressive pictures, where an older picture beats
    /// none while the camera keeps moving. Set before the first submit.
    bool keep_superseded = false;

private:
    void run() {
        std::unique_lock lock(mutex_);
        for (;;) {
            wake_.wait(lock, [this] { return quit_ || pending_ != nullptr; });
            if (quit_) return;
            std::function<Result()> work = std::move(pending_);
            pending_ = nullptr;
            const unsigned long id = newest_;
            running_ = true;
            lock.unlock();
            Result result = work();
            lock.lock();
            running_ = false;
            if (id == newest_ || keep_superseded) {
                finished_ = std::move(result);
                if (on_finished) on_finished();
            }
            done_.notify_all();
        }
    }

    mutable std::mutex mutex_;
    std::condition_variable wake_, done_;
    std::function<Result()> pending_;
    std::optional<Result> finished_;
    unsigned long newest_ = 0;
    bool running_ = false;
    bool quit_ = false;
    std::thread worker_;  ///< last: starts when the rest exists
};

}  // namespace accelviz
