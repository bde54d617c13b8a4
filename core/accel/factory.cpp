#include "core/accel/factory.h"

#include "core/accel/brute_force.h"

namespace accelviz {

const std::vector<std::string>& accel_types() {
    static const std::vector<std::string> types = {"naive"};
    return types;
}

Expected<std::shared_ptr<const Accelerator>> build_accelerator(const Mesh& mesh, const AccelConfig& config) {
    if (config.type == "naive")
        return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<BruteForce>>(BruteForce(mesh)));
    return Error{"unknown structure '" + config.type + "'"};
}

}  // namespace accelviz
