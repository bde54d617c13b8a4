#include "core/util/large_array.h"

#include <cassert>
#include <cstdint>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace accelviz {

namespace {
constexpr size_t kHugePage = LargeArrayAllocator<char>::kHugePage;
}

// Under the sanitizers the blocks come from malloc, whose blocks AddressSanitizer
// guards (overflows, use after free) and LeakSanitizer tracks.
#if defined(__linux__) && !defined(ACCELVIZ_SANITIZED)
namespace {
/// `bytes` mapped on their own, starting on a huge-page boundary: one huge page more
/// is mapped, so that an aligned start lies inside, and the slack before and after
/// it is given back at once.
char* take_aligned_block(size_t bytes) {
    const size_t span = bytes + kHugePage;
    void* mapped = mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mapped == MAP_FAILED) throw std::bad_alloc();
    char* const start = static_cast<char*>(mapped);
    char* const block =
        reinterpret_cast<char*>((reinterpret_cast<uintptr_t>(start) + kHugePage - 1) & ~uintptr_t(kHugePage - 1));
    if (block > start) munmap(start, size_t(block - start));
    if (start + span > block + bytes) munmap(block + bytes, size_t(start + span - (block + bytes)));
    return block;
}
}  // namespace

void free_huge_block(void* block, size_t bytes) { munmap(block, bytes); }
#else
namespace {
char* take_aligned_block(size_t bytes) {
    void* block = std::aligned_alloc(kHugePage, bytes);
    if (!block) throw std::bad_alloc();
    return static_cast<char*>(block);
}
}  // namespace

void free_huge_block(void* block, size_t) { std::free(block); }
#endif

void* allocate_huge_block(size_t bytes) {
    assert(bytes % kHugePage == 0);
    char* const block = take_aligned_block(bytes);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(block, bytes, MADV_HUGEPAGE);  // advice only: no error if refused
#endif
    return block;
}

void touch_pages_in_parallel(void* p, size_t bytes) {
    constexpr size_t kPage = 4096;
    char* const bytes_at = static_cast<char*>(p);
    // Pieces of 1-2 MiB: few tasks, each of a whole huge page's worth of writes.
    constexpr size_t kPiece = kHugePage;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, bytes, kPiece), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t at = r.begin(); at < r.end(); at += kPage) bytes_at[at] = 0;
    });
}

}  // namespace accelviz
