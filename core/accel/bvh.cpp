#include "core/accel/bvh.h"

namespace accelviz {

nlohmann::json Bvh::config() const {
    nlohmann::json j = to_json(build_config);
    j["traversal"] = to_string(traversal);
    j["triangle_test"] = to_string(triangle_test);
    return j;
}

nlohmann::json Bvh::stats() const { return to_json(build_stats); }

ACCELVIZ_BVH_TRAVERSALS(, MollerTrumbore)

}  // namespace accelviz
