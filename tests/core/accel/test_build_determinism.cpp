// Builds are deterministic (label slow: about 20 s): the same mesh and configuration give the same
// structure on every run and on any number of threads. A structure is compared
// by what it reports (its stats, wall times aside) and by every traversal event
// of seeded rays (node indices, boxes, triangle ids and t): two structures that
// walk every ray through the same nodes in the same order are the same tree.
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "accel_test_support.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "core/traversal/event_json.h"

namespace accelviz {
namespace {

struct Fingerprint {
    std::string stats;          ///< stats() without build_ms
    size_t events_hash = 0;     ///< hash of every event of every ray, as JSON text
    size_t event_count = 0;
    bool operator==(const Fingerprint&) const = default;
};

Fingerprint fingerprint(const Mesh& mesh, const AccelConfig& config, const std::vector<Ray>& rays) {
    auto built = build_accelerator(mesh, config);
    EXPECT_TRUE(built) << built.error();
    if (!built) return {};
    const Accelerator& accel = **built;
    Fingerprint out;
    nlohmann::json stats = accel.stats();
    // Wall times (build_ms, and the wide BVH's collapse_ms and its binary tree's) vary run to run.
    std::function<void(nlohmann::json&)> drop_times = [&](nlohmann::json& j) {
        if (!j.is_object()) return;
        for (auto it = j.begin(); it != j.end();) {
            if (it.key().ends_with("_ms")) it = j.erase(it);
            else drop_times(*it++);
        }
    };
    drop_times(stats);
    out.stats = stats.dump();
    std::string all;
    for (const Ray& ray : rays) {
        RecordingObserver recorder;
        accel.intersect_closest(ray, recorder);
        out.event_count += recorder.events.size();
        all += to_json(recorder.events).dump();
    }
    out.events_hash = std::hash<std::string>{}(all);
    return out;
}

TEST(BuildDeterminism, TheFingerprintTellsTwoTreesApart) {
    auto mesh = load_scene("builtin:soup?n=2000&seed=11");
    ASSERT_TRUE(mesh) << mesh.error();
    const std::vector<Ray> rays = test::make_test_rays(*mesh, 50, 5);
    AccelConfig a, b;
    a.type = b.type = AccelType::Bvh;
    a.bvh.bins = 16;
    b.bvh.bins = 15;  // one bucket fewer: a slightly different tree, the same hits
    const Fingerprint fa = fingerprint(*mesh, a, rays), fb = fingerprint(*mesh, b, rays);
    EXPECT_NE(fa.stats, fb.stats);
    EXPECT_NE(fa.events_hash, fb.events_hash);
}

TEST(BuildDeterminism, SameStructureOnEveryRunAndAnyNumberOfThreadsSlow) {
    // Big enough that the KD tree builds subtrees in parallel (below 4096 references).
    for (const char* source : {"builtin:soup?n=12000&seed=11", "builtin:teapot", "builtin:same-box"}) {
        auto mesh = load_scene(source);
        ASSERT_TRUE(mesh) << mesh.error();
        const std::vector<Ray> rays = test::make_test_rays(*mesh, 200, 5);
        for (const auto& [label, config] : test::all_configurations()) {
            SCOPED_TRACE(std::string(source) + ", " + label);
            const Fingerprint first = fingerprint(*mesh, config, rays);
            const Fingerprint again = fingerprint(*mesh, config, rays);
            Fingerprint one_thread;
            {
                tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
                one_thread = fingerprint(*mesh, config, rays);
            }
            EXPECT_GT(first.event_count, rays.size());
            EXPECT_EQ(first, again) << "two runs built different structures";
            EXPECT_EQ(first, one_thread) << "one thread built another structure than all threads";
        }
    }
}

}  // namespace
}  // namespace accelviz
