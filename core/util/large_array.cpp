#include "core/util/large_array.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace accelviz {

void touch_pages_in_parallel(void* p, size_t bytes) {
    constexpr size_t kPage = 4096;
    char* const bytes_at = static_cast<char*>(p);
    // Pieces of 1-2 MiB: few tasks, each of a whole huge page's worth of writes.
    constexpr size_t kPiece = size_t(2) << 20;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, bytes, kPiece), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t at = r.begin(); at < r.end(); at += kPage) bytes_at[at] = 0;
    });
}

}  // namespace accelviz
