#include "core/accel/factory.h"

#include "core/accel/brute_force.h"
#include "core/accel/bvh_build.h"

namespace accelviz {

const std::vector<std::string>& accel_types() {
    static const std::vector<std::string> types = {"naive", "bvh", "grid", "kd", "octree"};
    return types;
}

Expected<std::shared_ptr<const Accelerator>> build_accelerator(const Mesh& mesh, const AccelConfig& config) {
    if (config.type == "naive")
        return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<BruteForce>>(BruteForce(mesh)));
    if (config.type == "bvh") {
        BvhConfig bvh_config = config.bvh;  // the shared flags, when given, override
        if (config.leaf_size) bvh_config.max_leaf_size = *config.leaf_size;
        if (config.cost_trav) bvh_config.cost_trav = *config.cost_trav;
        if (config.cost_isect) bvh_config.cost_isect = *config.cost_isect;
        if (auto err = validate(bvh_config)) return *err;
        Bvh bvh = build_bvh(mesh, bvh_config);
        bvh.traversal = config.bvh_traversal;
        return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<Bvh>>(std::move(bvh)));
    }
    if (config.type == "grid") {
        auto grid = build_uniform_grid(mesh, config.grid);
        if (!grid) return Error{grid.error()};
        return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<UniformGrid>>(std::move(*grid)));
    }
    if (config.type == "kd") {
        KdConfig kd = config.kd;
        if (config.leaf_size) kd.leaf_size = *config.leaf_size;
        if (config.cost_trav) kd.cost_trav = *config.cost_trav;
        if (config.cost_isect) kd.cost_isect = *config.cost_isect;
        auto tree = build_kd_tree(mesh, kd);
        if (!tree) return Error{tree.error()};
        return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<KdTree>>(std::move(*tree)));
    }
    if (config.type == "octree") {
        OctreeConfig octree = config.octree;
        if (config.leaf_size) octree.leaf_size = *config.leaf_size;
        auto tree = build_octree(mesh, octree);
        if (!tree) return Error{tree.error()};
        return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<Octree>>(std::move(*tree)));
    }
    return Error{"unknown structure '" + config.type + "'"};
}

}  // namespace accelviz
