#pragma once
/// Builds the structure the user picked (`--accel`), with its configuration.

#include <memory>
#include <optional>
#include <string>

#include "core/accel/accelerator.h"
#include "core/accel/bsp_tree.h"
#include "core/accel/kd_tree.h"
#include "core/accel/octree.h"
#include "core/accel/uniform_grid.h"
#include "core/accel/bvh_config.h"
#include "core/util/expected.h"
#include "core/util/work_progress.h"

namespace accelviz {

/// Every structure's build parameters in one place (the CLI flags and the
/// Structure panel both write here).
struct AccelConfig {
    AccelType type = AccelType::Naive;

    // Space partitioning. Each structure's own parameters; --mailbox sets all three.
    GridConfig grid;      ///< --grid-*
    KdConfig kd;          ///< --kd-*
    OctreeConfig octree;  ///< --octree-*
    BspConfig bsp;        ///< --bsp-*
    /// Flags several structures share; unset = each structure's own default.
    /// (bvh, kd, octree and bsp read them here; a structure without such a parameter ignores them.)
    std::optional<int> leaf_size;     ///< --leaf-size
    std::optional<float> cost_trav;   ///< --cost-trav  (SAH C_trav)
    std::optional<float> cost_isect;  ///< --cost-isect (SAH C_isect)
    BvhConfig bvh;               ///< bvh: --bvh-build --bins --leaf-size --cost-trav --cost-isect
    BvhTraversal bvh_traversal = BvhTraversal::Ordered;  ///< bvh: --bvh-traversal
    /// Every structure: --triangle-test (set after the build; the wide BVH's and the KD
    /// tree's SAH weigh leaves by it: Möller–Trumbore tests four triangles at a time).
    TriangleTestKind triangle_test = TriangleTestKind::MollerTrumbore;
    /// Every structure: the bytes its build may take (--memory-budget; 0 = half the
    /// physical memory). Not part of what a preset or the panels describe.
    uint64_t memory_budget = 0;
    /// A structure read from this file (docs/structure-format.md; e.g. a student's
    /// tree, `--structure`) instead of one built: when set, the other fields are
    /// ignored (the file says what it is; leaves run Möller–Trumbore) and a file that is
    /// not valid over the mesh is an error naming its first problem.
    std::string structure_file;
};

/// AccelConfig's defaults with type "bvh".
inline AccelConfig bvh_config_default() {
    AccelConfig config;
    config.type = AccelType::Bvh;
    return config;
}

/// Whether the structure `config.type` can be built with these parameters (the
/// shared flags applied over its own); the first bad one as a one-line message naming
/// its command-line flag. build_accelerator() checks the same.
std::optional<Error> validate(const AccelConfig& config);

/// Builds the structure over `mesh`. Errors are one-line messages (bad parameter,
/// or a build that would not fit the memory budget: core/accel/memory_budget.h).
/// `progress` hears how far the build has got (a stage of its own units) and may
/// cancel it: the build then returns WorkProgress::cancelled_error().
Expected<std::shared_ptr<const Accelerator>> build_accelerator(const Mesh& mesh, const AccelConfig& config,
                                                               WorkProgress* progress = nullptr);

/// A binary BVH's update for a moving scene: a copy of `built` (a Bvh) refitted to
/// `after`, the mesh it was built over with its vertices moved (refit_bvh in
/// bvh_build.h). Its build_stats.refit_ms times the refit alone, not the copy. Any
/// other structure, or another triangle count, is an error.
Expected<std::shared_ptr<const Accelerator>> refit_accelerator(const Accelerator& built, const Mesh& after);

/// The build parameters of the binary BVH behind `accel`: a Bvh's own, or those of
/// the binary tree a wide BVH was collapsed from (width 2). Nothing for any other
/// structure. Building a Bvh with them again gives the same binary tree.
std::optional<BvhConfig> binary_bvh_config(const Accelerator& accel);

}  // namespace accelviz
