// libFuzzer target: bytes as OBJ text, through loading, building every structure
// and tracing seeded rays of the kinds that break structures (accel_test_support.h).
// A load error is a right answer to bad input; a crash, an escaped exception, or a
// hit that differs from brute force (another triangle, or t not bit-identical) is
// a finding, and aborts.
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "accel/accel_test_support.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"

namespace {

using namespace accelviz;

/// Small enough that one input takes milliseconds, so the fuzzer tries many.
constexpr size_t kMaxTriangles = 3000;
constexpr size_t kRays = 64;

std::vector<AccelConfig> structures() {
    std::vector<AccelConfig> out;
    for (BvhBuilder builder : {BvhBuilder::SahBinned, BvhBuilder::Midpoint}) {
        AccelConfig c;
        c.type = AccelType::Bvh;
        c.bvh.builder = builder;
        out.push_back(c);
    }
    AccelConfig unordered;
    unordered.type = AccelType::Bvh;
    unordered.bvh_traversal = BvhTraversal::Unordered;
    out.push_back(unordered);
    for (GridInsert insert : {GridInsert::Box, GridInsert::Exact}) {
        AccelConfig c;
        c.type = AccelType::Grid;
        c.grid.insert = insert;
        out.push_back(c);
    }
    for (ClipMode clip : {ClipMode::Box, ClipMode::Exact}) {
        AccelConfig kd;
        kd.type = AccelType::Kd;
        kd.kd.clip = clip;
        kd.kd.mailbox = clip == ClipMode::Box;
        out.push_back(kd);
        AccelConfig octree;
        octree.type = AccelType::Octree;
        octree.octree.clip = clip;
        out.push_back(octree);
    }
    return out;
}

[[noreturn]] void mismatch(const AccelConfig& config, const Ray& ray, const Hit& got, const Hit& want) {
    std::fprintf(stderr,
                 "%s differs from brute force: ray (%a %a %a) -> (%a %a %a) [%a, %a]: tri %u t %a, brute force tri %u "
                 "t %a\n",
                 std::string(to_string(config.type)).c_str(), ray.origin.x, ray.origin.y, ray.origin.z, ray.dir.x,
                 ray.dir.y, ray.dir.z, ray.t_min, ray.t_max, got.tri, got.t, want.tri, want.t);
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    auto mesh = parse_obj(std::string(reinterpret_cast<const char*>(data), size), "fuzz.obj");
    if (!mesh || mesh->triangle_count() > kMaxTriangles) return 0;
    const std::vector<Ray> rays = test::make_test_rays(*mesh, kRays, size);
    auto brute = build_accelerator(*mesh, AccelConfig{});  // the default: naive, every triangle per ray
    if (!brute) std::abort();
    std::vector<Hit> want;
    for (const Ray& ray : rays) want.push_back((*brute)->intersect_closest(ray));
    for (const AccelConfig& config : structures()) {
        auto built = build_accelerator(*mesh, config);
        if (!built) {
            std::fprintf(stderr, "%s: %s\n", std::string(to_string(config.type)).c_str(), built.error().c_str());
            std::abort();  // a mesh that loaded must build
        }
        for (size_t i = 0; i < rays.size(); ++i) {
            const Hit got = (*built)->intersect_closest(rays[i]);
            if (got.tri != want[i].tri || std::bit_cast<uint32_t>(got.t) != std::bit_cast<uint32_t>(want[i].t))
                mismatch(config, rays[i], got, want[i]);
            if ((*built)->intersect_any(rays[i]) != want[i].found()) mismatch(config, rays[i], got, want[i]);
        }
    }
    return 0;
}
