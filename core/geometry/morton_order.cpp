#include "core/geometry/morton_order.h"

#include <algorithm>
#include <array>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/util/large_array.h"

namespace accelviz {

namespace {

/// The 10 low bits of v spread to every third bit.
uint32_t spread_bits(uint32_t v) {
    v &= 0x3ffu;
    v = (v | v << 16) & 0x030000ffu;
    v = (v | v << 8) & 0x0300f00fu;
    v = (v | v << 4) & 0x030c30c3u;
    v = (v | v << 2) & 0x09249249u;
    return v;
}

}  // namespace

uint32_t morton_code(uint32_t x, uint32_t y, uint32_t z) { return spread_bits(x) | spread_bits(y) << 1 | spread_bits(z) << 2; }

std::vector<uint32_t> morton_order(const Mesh& mesh, const Aabb& bounds) {
    const size_t n = mesh.triangle_count();
    constexpr uint32_t kCells = 1u << 10;
    // Key: the code above the id, so that sorting keys sorts by code, then id.
    // On huge pages, faulted in by all threads (large_array.h): at ten million
    // triangles these are 160 MB that a first build would otherwise fault in page by page.
    using Keys = std::vector<uint64_t, LargeArrayAllocator<uint64_t>>;
    Keys keys = make_prefaulted<Keys>(n), scratch = make_prefaulted<Keys>(n);
    const Vec3 size = bounds.hi - bounds.lo;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 8192), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t t = r.begin(); t < r.end(); ++t) {
            const Vec3 c = mesh.triangle_bounds(t).center();
            uint32_t cell[3];
            for (int a = 0; a < 3; ++a) {
                const float f = size[a] > 0 ? (c[a] - bounds.lo[a]) / size[a] * float(kCells) : 0.0f;
                cell[a] = f >= 0.0f ? uint32_t(std::min(f, float(kCells - 1))) : 0u;  // NaN: 0
            }
            keys[t] = uint64_t(morton_code(cell[0], cell[1], cell[2])) << 32 | t;
        }
    });
    // Least significant digit first, three passes of 10 bits over the 30-bit codes: a
    // stable counting sort per digit, so ties (and the ids, in order from the start) stay in order.
    for (int shift = 32; shift < 62; shift += 10) {
        std::array<size_t, 1024> start{};
        for (uint64_t k : keys) ++start[k >> shift & 1023];
        size_t sum = 0;
        for (size_t& s : start) sum += std::exchange(s, sum);
        for (uint64_t k : keys) scratch[start[k >> shift & 1023]++] = k;
        keys.swap(scratch);
    }
    std::vector<uint32_t> order(n);
    for (size_t i = 0; i < n; ++i) order[i] = uint32_t(keys[i]);
    return order;
}

}  // namespace accelviz
