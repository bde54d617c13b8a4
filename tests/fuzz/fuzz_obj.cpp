// libFuzzer target: bytes as OBJ text, through loading, building every structure
// and tracing seeded rays of the kinds that break structures (accel_test_support.h).
// A load error is a right answer to bad input; a crash, an escaped exception, or a
// hit that differs from brute force (another triangle, or t not bit-identical) is
// a finding, and aborts.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "accel/accel_test_support.h"
#include "core/geometry/scene.h"

namespace {

using namespace accelviz;

/// Small enough that one input takes milliseconds, so the fuzzer tries many.
constexpr size_t kMaxTriangles = 3000;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    auto mesh = parse_obj(std::string(reinterpret_cast<const char*>(data), size), "fuzz.obj");
    if (!mesh || mesh->triangle_count() > kMaxTriangles) return 0;
    const std::vector<Ray> rays = test::fuzz_rays(*mesh, size);
    if (const auto wrong = test::first_disagreement(*mesh, rays)) {
        std::fprintf(stderr, "%s\n", wrong->c_str());
        std::abort();
    }
    return 0;
}
