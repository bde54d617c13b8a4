#pragma once
/// Progress of a long step on stderr. A step that runs for more than two seconds
/// (loading a big OBJ, building a structure over millions of triangles) gets a line
/// when it has run that long and one when it ends, so that a command working for a
/// minute does not look hung; shorter steps print nothing. `--quiet` turns the
/// lines off. (ACCELVIZ_PROGRESS_AFTER_MS sets the two seconds, for tests.)

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace accelviz::cli {

/// On (the default) or off (--quiet), for every later step.
void set_progress_lines(bool on);

/// Lives as long as the step: "accelviz COMMAND: WHAT ..." once the step has run for
/// the threshold, then "accelviz COMMAND: WHAT: 9.4 s" when it ends.
class StepProgress {
public:
    StepProgress(std::string command, std::string what);
    ~StepProgress();
    StepProgress(const StepProgress&) = delete;
    StepProgress& operator=(const StepProgress&) = delete;

private:
    std::string prefix_;  ///< "accelviz COMMAND: WHAT"
    std::chrono::steady_clock::time_point start_;
    std::mutex mutex_;
    std::condition_variable ended_;
    bool done_ = false;
    bool printed_ = false;  ///< written by the watcher, read after it has joined
    std::thread watcher_;
};

}  // namespace accelviz::cli
