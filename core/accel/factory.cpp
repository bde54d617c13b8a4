#include "core/accel/factory.h"

#include "core/exchange/structure_check.h"

#include "core/accel/brute_force.h"
#include "core/accel/bvh_build.h"
#include "core/accel/memory_budget.h"
#include "core/accel/wide_bvh.h"

namespace accelviz {

namespace {

/// A structure's own parameters with the shared flags, when given, over them (a
/// structure without a cost model passes no cost members).
template <class Config>
Config with_shared_flags(Config own, const AccelConfig& config, int Config::*leaf_size,
                         float Config::*cost_trav = nullptr, float Config::*cost_isect = nullptr) {
    if (config.leaf_size) own.*leaf_size = *config.leaf_size;
    if (cost_trav && config.cost_trav) own.*cost_trav = *config.cost_trav;
    if (cost_isect && config.cost_isect) own.*cost_isect = *config.cost_isect;
    return own;
}
/// The triangle test a built structure runs; the watertight test also needs the
/// corners, in the structure's order (`order`: leaf order, the octree's copy_order, or
/// empty for by id).
template <class Structure>
void use_triangle_test(Structure& s, TriangleTestKind test, const Mesh& mesh, std::span<const uint32_t> order) {
    s.triangle_test = test;
    if (test == TriangleTestKind::Watertight) s.corners = make_corners(mesh, order);
}

BvhConfig bvh_config_of(const AccelConfig& config) {
    BvhConfig c =
        with_shared_flags(config.bvh, config, &BvhConfig::max_leaf_size, &BvhConfig::cost_trav, &BvhConfig::cost_isect);
    // The wide BVH's leaves test leaf_lanes_for(test) triangles together; the lecture's
    // binary tree tests one at a time.
    c.leaf_lanes = c.width != 2 ? leaf_lanes_for(config.triangle_test) : 1;
    return c;
}
KdConfig kd_config_of(const AccelConfig& config) {
    KdConfig c = with_shared_flags(config.kd, config, &KdConfig::leaf_size, &KdConfig::cost_trav, &KdConfig::cost_isect);
    c.leaf_lanes = leaf_lanes_for(config.triangle_test);
    return c;
}
OctreeConfig octree_config_of(const AccelConfig& config) {
    return with_shared_flags(config.octree, config, &OctreeConfig::leaf_size);
}
BspConfig bsp_config_of(const AccelConfig& config) {
    return with_shared_flags(config.bsp, config, &BspConfig::leaf_size, &BspConfig::cost_trav, &BspConfig::cost_isect);
}

/// The binary tree collapsed into a W-wide one.
template <int W>
Expected<std::shared_ptr<const Accelerator>> wide_accelerator(Bvh&& binary, WorkProgress* progress) {
    auto wide = collapse_bvh<W>(std::move(binary), progress);
    if (!wide) return Error{wide.error()};
    return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<WideBvh<W>>>(std::move(*wide)));
}

}  // namespace

std::optional<Error> validate(const AccelConfig& config) {
    switch (config.type) {
        case AccelType::Naive: return std::nullopt;
        case AccelType::Bvh: return validate(bvh_config_of(config));
        case AccelType::Grid: return validate(config.grid);
        case AccelType::Kd: return validate(kd_config_of(config));
        case AccelType::Octree: return validate(octree_config_of(config));
        case AccelType::Bsp: return validate(bsp_config_of(config));
    }
    return Error{"unknown structure"};
}

Expected<std::shared_ptr<const Accelerator>> build_accelerator(const Mesh& mesh, const AccelConfig& requested,
                                                               WorkProgress* progress) {
    if (!requested.structure_file.empty()) {
        start_stage(progress, 0);
        return load_structure_file(requested.structure_file, mesh, "");
    }
    if (auto err = validate(requested)) return *err;
    std::string budget_note;  // what the memory budget lowered, if anything
    const Expected<AccelConfig> fitted =
        fit_memory_budget(requested, mesh.triangle_count(), requested.memory_budget, &budget_note);
    if (!fitted) return Error{fitted.error()};
    const AccelConfig& config = *fitted;
    auto with_note = [&](auto& stats) {
        if (!budget_note.empty()) stats.notes.push_back(budget_note);
    };
    switch (config.type) {
        case AccelType::Naive:
            start_stage(progress, 0);
            return std::shared_ptr<const Accelerator>(
                std::make_shared<AcceleratorFor<BruteForce>>(BruteForce(mesh, config.triangle_test)));
        case AccelType::Bvh: {
            auto bvh = build_bvh(mesh, bvh_config_of(config), nullptr, progress);
            if (!bvh) return Error{bvh.error()};
            bvh->traversal = config.bvh_traversal;
            use_triangle_test(*bvh, config.triangle_test, mesh, bvh->prim_ids);
            switch (bvh_config_of(config).width) {
                case 4: return wide_accelerator<4>(std::move(*bvh), progress);
                case 8: return wide_accelerator<8>(std::move(*bvh), progress);
                default: break;
            }
            return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<Bvh>>(std::move(*bvh)));
        }
        case AccelType::Grid: {
            auto grid = build_uniform_grid(mesh, config.grid, progress);
            if (!grid) return Error{budget_note.empty() ? grid.error() : grid.error() + " (" + budget_note + ")"};
            with_note(grid->build_stats);
            use_triangle_test(*grid, config.triangle_test, mesh, {});
            return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<UniformGrid>>(std::move(*grid)));
        }
        case AccelType::Kd: {
            auto tree = build_kd_tree(mesh, kd_config_of(config), progress);
            if (!tree) return Error{tree.error()};
            with_note(tree->build_stats);
            use_triangle_test(*tree, config.triangle_test, mesh, tree->triangle_order());
            return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<KdTree>>(std::move(*tree)));
        }
        case AccelType::Octree: {
            auto tree = build_octree(mesh, octree_config_of(config), progress);
            if (!tree) return Error{tree.error()};
            with_note(tree->build_stats);
            use_triangle_test(*tree, config.triangle_test, mesh, tree->triangle_order());
            return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<Octree>>(std::move(*tree)));
        }
        case AccelType::Bsp: {
            auto tree = build_bsp_tree(mesh, bsp_config_of(config), progress);
            if (!tree) return Error{tree.error()};
            with_note(tree->build_stats);
            use_triangle_test(*tree, config.triangle_test, mesh, tree->triangle_order());
            return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<BspTree>>(std::move(*tree)));
        }
    }
    return Error{"unknown structure"};
}

Expected<std::shared_ptr<const Accelerator>> refit_accelerator(const Accelerator& built, const Mesh& after) {
    const Bvh* bvh = structure_if<Bvh>(built);
    if (!bvh) return Error{"only the binary BVH refits (--accel bvh --bvh-width 2)"};
    Bvh refitted = *bvh;
    if (auto error = refit_bvh(refitted, after)) return *error;
    gather_refit_stats(refitted);
    return std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<Bvh>>(std::move(refitted)));
}

std::optional<BvhConfig> binary_bvh_config(const Accelerator& accel) {
    std::optional<BvhConfig> config;
    if (const auto* bvh = structure_if<Bvh>(accel)) config = bvh->build_config;
    else if (const auto* wide4 = structure_if<WideBvh<4>>(accel)) config = wide4->build_config;
    else if (const auto* wide8 = structure_if<WideBvh<8>>(accel)) config = wide8->build_config;
    if (config) config->width = 2;
    return config;
}

}  // namespace accelviz
