#include "core/accel/bvh.h"

namespace accelviz {

nlohmann::json Bvh::config() const {
    nlohmann::json j = to_json(build_config);
    j["traversal"] = to_string(traversal);
    return j;
}

nlohmann::json Bvh::stats() const { return to_json(build_stats); }

ACCELVIZ_BVH_TRAVERSALS(, NoObserver)
ACCELVIZ_BVH_TRAVERSALS(, CountingObserver)
ACCELVIZ_BVH_TRAVERSALS(, RecordingObserver)

}  // namespace accelviz
