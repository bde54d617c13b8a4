/// Linked into every program of the ThreadSanitizer build (scripts/test --tsan) and
/// no other: oneTBB's task scheduler runs on the calling thread alone.
///
/// Why: Debian's oneTBB is not instrumented, so ThreadSanitizer cannot see that a
/// parallel_for has joined its tasks, and reports every later read of what they
/// wrote as a race with a worker whose stack it does not know. With one thread
/// allowed, the tasks run on the thread that called parallel_for and those false
/// reports go; the program's own threads (the window's load, build, ray-cast and
/// stepper jobs: std::thread, std::mutex, std::condition_variable) are still
/// checked in full. A tbb::global_control with a larger limit made later cannot
/// raise it: TBB uses the smallest limit alive.
#include <tbb/global_control.h>

namespace {
const tbb::global_control tbb_on_the_calling_thread_only(tbb::global_control::max_allowed_parallelism, 1);
}  // namespace
