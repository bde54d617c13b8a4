// libFuzzer target: bytes as a structure file (docs/structure-format.md), JSON or
// binary, over a small fixed mesh. Malformed input must come back as an error and
// check_structure must judge anything that parses, never crash or hang; a file it
// calls valid must load for our traversal and be measured, and a valid BVH must
// find brute force's closest hit for every ray (what "valid" promises).
#include <cstdint>
#include <cstdlib>
#include <string>

#include "accel/accel_test_support.h"
#include "core/exchange/structure_check.h"
#include "core/exchange/structure_file.h"
#include "core/geometry/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace accelviz;
    static const Mesh mesh = *load_scene("builtin:cube", MeshCache::Skip);
    static const std::vector<Ray> rays = test::make_test_rays(mesh, 64, 5);
    static const std::vector<Hit> want = test::brute_force_answers(mesh, rays);
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    auto file = bytes.rfind("AVZSTRC1", 0) == 0 ? parse_structure_binary(bytes) : parse_structure_json(bytes);
    if (!file) return 0;
    const StructureCheck check = check_structure(*file, mesh, std::nullopt, 4);
    if (!check.valid()) return 0;
    auto accel = structure_accelerator(*file, mesh);
    if (!accel) std::abort();  // valid, yet our traversal cannot take it
    for (size_t r = 0; r < rays.size(); ++r) {
        const Hit hit = (*accel)->intersect_closest(rays[r]);
        if (file->type == AccelType::Bvh && !test::same_hit(hit, want[r])) std::abort();
    }
    // The figures check prints walk the valid tree once more (the SAH cost, depths).
    measure_structure(*file, mesh, **accel, std::span<const Ray>(rays.data(), 8), **accel, {});
    return 0;
}
