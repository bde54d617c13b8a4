#include "app/cli/accel_flags.h"
#include "app/cli/flag_checks.h"
#include "core/accel/memory_budget.h"

namespace accelviz::cli {

void add_accel_flags(CLI::App& command, AccelConfig& config) {
    // The command line's default is the BVH: naive is the lecture's O(N) baseline,
    // minutes per frame on a real mesh, so it is asked for by name.
    config.type = AccelType::Bvh;
    command.add_option_function<std::string>(
               "--accel", [&config](const std::string& v) { config.type = *parse_accel_type(v); },
               "Acceleration structure (naive = the O(N) baseline: every triangle per ray)")
        ->check(CLI::IsMember(accel_type_names()))
        ->default_str("bvh");

    command.add_option("--structure", config.structure_file,
                       "A structure from a file (docs/structure-format.md, e.g. a student's tree; accelviz check "
                       "says whether it is valid) instead of building one: the other structure flags are ignored");

    // Shared by several structures (unset: each structure's default).
    command.add_option("--leaf-size", config.leaf_size,
                       "Leaf size limit (bvh: 1.." + std::to_string(kBvhMaxLeafSize) +
                           "; kd, octree, bsp: any); default: each structure's own")
        ->check(whole_number(1, 1 << 20));
    command.add_option("--cost-trav", config.cost_trav, "SAH cost of one interior-node step, C_trav (bvh, kd, bsp)")
        ->check(number_between(0.0, 1e6));
    command.add_option("--cost-isect", config.cost_isect, "SAH cost of one ray-triangle test, C_isect (bvh, kd, bsp)")
        ->check(number_between(1e-6, 1e6));

    // BVH. --leaf-size, --cost-trav and --cost-isect above apply too (default 4, 1, 1).
    command.add_option_function<std::string>(
               "--bvh-build", [&config](const std::string& v) { config.bvh.builder = *parse_bvh_builder(v); },
               "bvh: how nodes are split: longest axis at its middle, at the median triangle, full SAH sweep, "
               "or binned SAH (midpoint|median|sah-sweep|sah-binned, default sah-binned)")
        ->check(CLI::IsMember(bvh_builder_names()));
    command.add_option("--bins", config.bvh.bins, "bvh sah-binned: buckets per axis, B in " + std::to_string(kBvhMinBins) + ".." +
                                                    std::to_string(kBvhMaxBins))
        ->check(whole_number(kBvhMinBins, kBvhMaxBins))
        ->capture_default_str();
    command.add_option_function<std::string>(
               "--bvh-traversal", [&config](const std::string& v) { config.bvh_traversal = *parse_bvh_traversal(v); },
               "bvh: closest-hit algorithm: 2 = nearest child first, skip nodes beyond the closest hit; "
               "1 = left then right, no pruning (ordered|unordered, default ordered)")
        ->check(CLI::IsMember(bvh_traversal_names()));
    command.add_option("--bvh-width", config.bvh.width,
                       "bvh: children per node: 2 = the lecture's binary tree; 4 or 8 = the binary tree collapsed, "
                       "its children's boxes tested together by SIMD instructions (the same leaves)")
        ->check(CLI::IsMember({2, 4, 8}))
        ->capture_default_str();

    command.add_option_function<std::string>(
               "--triangle-test", [&config](const std::string& v) { config.triangle_test = *parse_triangle_test(v); },
               "Ray-triangle test of every structure: Moller-Trumbore (the lecture's) or watertight (Woop, Benthin "
               "and Wald 2013: no ray slips between triangles sharing an edge) (mt|watertight, default mt)")
        ->check(CLI::IsMember(triangle_test_names()));

    command.add_option_function<std::string>(
               "--memory-budget",
               [&config](const std::string& v) { config.memory_budget = *parse_memory_size(v); },
               "Most memory a structure's build may take, e.g. 4G or 512M (default: half the physical memory, " +
                   format_bytes(default_memory_budget()) +
                   " here). A build that cannot fit is refused; the grid's, KD tree's and octree's references are "
                   "capped to fit (the Stats notes say so)")
        ->check(CLI::Validator(
            [](std::string& v) -> std::string {
                return parse_memory_size(v) ? "" : "must be a size such as 4G, 512M or 65536 (got " + v + ")";
            },
            "SIZE"));

    // Space partitioning: grid, kd, octree, bsp.
    auto on_off = [](bool& a) { return [&a](const std::string& v) { a = v == "on"; }; };
    command.add_option_function<std::string>(
               "--mailbox",
               [&config](const std::string& v) {
                   config.grid.mailbox = config.kd.mailbox = config.octree.mailbox = config.bsp.mailbox = v == "on";
               },
               "grid/kd/octree/bsp: skip triangles a ray already tested in an earlier cell "
               "(on|off; default on for grid, octree and bsp, off for kd)")
        ->check(CLI::IsMember({"on", "off"}));
    command.add_option("--grid-density", config.grid.density, "grid: C in #cells = C * #triangles (lecture: 27)")
        ->check(number_between(0.001, 10000.0))
        ->capture_default_str();
    command.add_option_function<std::string>(
               "--grid-insert", [&config](const std::string& v) { config.grid.insert = *parse_grid_insert(v); },
               "grid: cells a triangle goes into: those its box overlaps, or those it overlaps (box|exact, default box)")
        ->check(CLI::IsMember(grid_insert_names()));
    command.add_option("--grid-max-cells-per-axis", config.grid.max_cells_per_axis, "grid: resolution cap per axis (reported when it applies)")
        ->check(whole_number(1, kBspMaxCandidates))
        ->capture_default_str();
    command.add_option_function<std::string>(
               "--kd-build", [&config](const std::string& v) { config.kd.builder = *parse_kd_builder(v); },
               "kd: plane choice, spatial median or SAH (median|sah, default sah)")
        ->check(CLI::IsMember(kd_builder_names()));
    command.add_option_function<std::string>("--kd-strict-cell", on_off(config.kd.strict_cell),
                                             "kd: a hit counts only inside the current leaf (on|off, default on; "
                                             "off shows the lecture's wrong answers)")
        ->check(CLI::IsMember({"on", "off"}));
    command.add_option("--kd-max-depth", config.kd.max_depth, "kd: max depth, 0 = 8 + 1.3*log2(N)")
        ->check(whole_number(0, kKdMaxDepth))
        ->capture_default_str();
    command.add_option("--kd-empty-bonus", config.kd.empty_bonus, "kd SAH: cost discount for cutting off empty space, in [0, 1)")
        ->check(number_between(0.0, 0.999))
        ->capture_default_str();
    command.add_option_function<std::string>(
               "--kd-clip", [&config](const std::string& v) { config.kd.clip = config.octree.clip = *parse_clip_mode(v); },
               "kd/octree: where a straddling triangle goes: exact (only the sides it reaches; the KD tree clips it to each) or box (every side its box reaches) (box|exact, default exact)")
        ->check(CLI::IsMember(clip_mode_names()));
    command.add_option("--octree-max-depth", config.octree.max_depth, "octree: max depth")
        ->check(whole_number(1, kOctreeMaxDepth))
        ->capture_default_str();
    command.add_option("--bsp-max-depth", config.bsp.max_depth, "bsp: max depth")
        ->check(whole_number(1, kBspMaxDepth))
        ->capture_default_str();
    command.add_option("--bsp-candidates", config.bsp.candidates,
                       "bsp: triangle planes tried per node (an even sample of its triangles)")
        ->check(whole_number(1, 4096))
        ->capture_default_str();
}

}  // namespace accelviz::cli
