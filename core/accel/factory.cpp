#include "core/accel/factory.h"

#include "core/accel/brute_force.h"
#include "core/accel/bvh_build.h"

namespace accelviz {

const std::vector<std::string>& accel_types() {
    static const std::vector<std::string> types = {"naive", "bvh"};
    return types;
}

Expected<std::shared_ptr<const Accelerator>> build_accelerator(const Mesh& mesh, const AccelConfig& config) {
    if (config.type == "naive")
        return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<BruteForce>>(BruteForce(mesh)));
    if (config.type == "bvh") {
        if (auto err = validate(config.bvh)) return *err;
        Bvh bvh = build_bvh(mesh, config.bvh);
        bvh.traversal = config.bvh_traversal;
        return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<Bvh>>(std::move(bvh)));
    }
    return Error{"unknown structure '" + config.type + "'"};
}

}  // namespace accelviz
