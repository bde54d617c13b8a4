#pragma once
/// An allocator for the big flat arrays of the acceleration structures (nodes,
/// triangles in leaf order, triangle ids) and of their builders.
///
/// Blocks of kHugePage bytes or more are mapped from the kernel on their own
/// (Linux: mmap; elsewhere, and under the sanitizers, aligned_alloc), start on a
/// kHugePage boundary and are marked for transparent huge pages
/// (madvise(MADV_HUGEPAGE)). A traversal of an 871k-triangle BVH then touches a few
/// dozen 2 MiB pages instead of thousands of 4 KiB ones (each a TLB entry to find),
/// and the build takes a few dozen page faults instead of ~25,000. Production ray
/// tracers do the same (Embree uses huge pages on Linux by default). Not from
/// malloc: after a big free, glibc raises its mmap threshold (up to 32 MiB) and
/// serves blocks below it from heap pages already faulted in as 4 KiB ones, so
/// whether an array of a few MiB to 32 MiB (an 871k-triangle BVH's nodes or
/// triangles) got huge pages depended on what the process had freed before it
/// (docs/performance.md). The advice is not a promise: where the kernel gives no
/// huge pages the memory is simply ordinary memory.
/// Smaller blocks come from aligned operator new.
///
/// kLeadBytes: the array starts that many bytes after a 64-byte (cache line)
/// boundary. The BVH uses sizeof(BvhNode) = 32 so that nodes[1], where the sibling
/// pairs begin, starts a cache line (see bvh.h).

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>

namespace accelviz {

/// `bytes` (a multiple of 2 MiB) of memory starting on a 2 MiB boundary, mapped
/// for this block alone (see LargeArrayAllocator) and marked for transparent huge
/// pages; std::bad_alloc if the system has none. Freed by free_huge_block with the same size.
void* allocate_huge_block(size_t bytes);
void free_huge_block(void* block, size_t bytes);

template <class T, size_t kLeadBytes = 0>
struct LargeArrayAllocator {
    using value_type = T;
    static constexpr size_t kLine = 64;
    static constexpr size_t kHugePage = size_t(2) << 20;
    static_assert(kLeadBytes < kLine && kLeadBytes % alignof(T) == 0);

    template <class U>
    struct rebind {
        using other = LargeArrayAllocator<U, kLeadBytes % alignof(U) == 0 ? kLeadBytes : 0>;
    };

    LargeArrayAllocator() = default;
    template <class U, size_t kOther>
    LargeArrayAllocator(const LargeArrayAllocator<U, kOther>&) {}

    T* allocate(size_t n) {
        if (n > (size_t(PTRDIFF_MAX) - 2 * kHugePage) / sizeof(T)) throw std::bad_array_new_length();
        const size_t bytes = block_bytes(n);
        char* block = nullptr;
        if (huge(bytes)) {
            block = static_cast<char*>(allocate_huge_block(bytes));
        } else {
            block = static_cast<char*>(::operator new(bytes, std::align_val_t(kLine)));
        }
        return reinterpret_cast<T*>(block + kLeadBytes);
    }

    void deallocate(T* p, size_t n) {
        char* block = reinterpret_cast<char*>(p) - kLeadBytes;
        const size_t bytes = block_bytes(n);
        if (huge(bytes)) free_huge_block(block, bytes);
        else ::operator delete(block, std::align_val_t(kLine));
    }

    template <class U, size_t kOther>
    bool operator==(const LargeArrayAllocator<U, kOther>&) const { return true; }

private:
    /// The whole block: the lead, the elements, rounded up to whole huge pages when huge.
    static size_t block_bytes(size_t n) {
        const size_t bytes = kLeadBytes + n * sizeof(T);
        return huge(bytes) ? (bytes + kHugePage - 1) / kHugePage * kHugePage : bytes;
    }
    static bool huge(size_t bytes) { return bytes >= kHugePage; }
};

/// Writes one byte in every 4 KiB page of [p, p + bytes), the pages shared out among
/// the threads (oneTBB): each page's first write makes the kernel find and zero it.
void touch_pages_in_parallel(void* p, size_t bytes);

/// A vector of `n` value-initialized elements whose pages all threads touch first
/// (touch_pages_in_parallel), before the vector value-initializes them on one. A fresh
/// page costs the kernel a zeroing and, on a virtual machine whose host takes freed
/// memory back, a fault on the host as well; an array of hundreds of megabytes that is
/// then filled in parallel (the BVH build's records, the space-partitioning builds'
/// root references, a big tree's leaf-ordered triangles) would pay those serially
/// (measured: docs/performance.md). Only for arrays made at their final size.
template <class Vector>
Vector make_prefaulted(size_t n) {
    Vector v;
    v.reserve(n);
    const size_t bytes = n * sizeof(typename Vector::value_type);
    if (bytes >= LargeArrayAllocator<char>::kHugePage) touch_pages_in_parallel(v.data(), bytes);
    v.resize(n);
    return v;
}

}  // namespace accelviz
