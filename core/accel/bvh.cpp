#include "core/accel/bvh.h"

namespace accelviz {

nlohmann::json Bvh::config() const {
    nlohmann::json j = to_json(build_config);
    j["traversal"] = to_string(traversal);
    return j;
}

nlohmann::json Bvh::stats() const { return to_json(build_stats); }

template Hit Bvh::intersect_ordered(const Ray&, NoObserver&) const;
template Hit Bvh::intersect_ordered(const Ray&, CountingObserver&) const;
template Hit Bvh::intersect_ordered(const Ray&, RecordingObserver&) const;
template Hit Bvh::intersect_unordered(const Ray&, NoObserver&) const;
template Hit Bvh::intersect_unordered(const Ray&, CountingObserver&) const;
template Hit Bvh::intersect_unordered(const Ray&, RecordingObserver&) const;
template bool Bvh::intersect_any(const Ray&, NoObserver&) const;
template bool Bvh::intersect_any(const Ray&, CountingObserver&) const;
template bool Bvh::intersect_any(const Ray&, RecordingObserver&) const;

}  // namespace accelviz
