#pragma once
/// Builds the structure the user picked (`--accel`), with its configuration.

#include <memory>
#include <string>

#include "core/accel/accelerator.h"
#include "core/accel/bvh_config.h"
#include "core/util/expected.h"

namespace accelviz {

/// Every structure's build parameters in one place (the CLI flags and the
/// Structure panel both write here).
struct AccelConfig {
    std::string type = "naive";  ///< naive | bvh (later: grid | kd | octree)
    BvhConfig bvh;               ///< bvh: --bvh-build --bins --leaf-size --cost-trav --cost-isect
    BvhTraversal bvh_traversal = BvhTraversal::Ordered;  ///< bvh: --bvh-traversal
};

/// The names `type` accepts.
const std::vector<std::string>& accel_types();

/// Builds the structure over `mesh`. Errors are one-line messages (bad parameter).
Expected<std::shared_ptr<const Accelerator>> build_accelerator(const Mesh& mesh, const AccelConfig& config);

}  // namespace accelviz
