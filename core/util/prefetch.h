#pragma once
/// prefetch(address): asks the memory system for the cache line holding `address`
/// before the code needs it, so a miss overlaps other work instead of stalling it.
/// Only a hint: it never faults (any address will do, even one outside every array)
/// and changes no result, only when memory arrives. The BVH's traversal and the build's
/// leaf-order copy use it where the hardware's own prefetcher was measured not to keep up.
///
/// The compiler may drop a hint: GCC 12 removed `if (k < end) prefetch(&refs[k])` from
/// the BVH build's binning and partition loops (no prefetch instruction in the binary,
/// while its gain had been "measured"). After adding one, look for it in the disassembly
/// (objdump -d | grep prefetch) before crediting it with a speed-up.

#include <cstddef>
#include <cstdint>

namespace accelviz {

inline void prefetch(const void* address) {
#if defined(__GNUC__) || defined(__clang__)
    __builtin_prefetch(address);
#else
    (void)address;
#endif
}

/// prefetch(&array[index]) computed as an integer, so `index` may lie outside the
/// array (reading nothing there is harmless; forming such a pointer would not be).
template <class T>
void prefetch_element(const T* array, size_t index) {
    prefetch(reinterpret_cast<const void*>(reinterpret_cast<uintptr_t>(array) + index * sizeof(T)));
}

}  // namespace accelviz
