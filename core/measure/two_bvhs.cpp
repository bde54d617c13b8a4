#include "core/measure/two_bvhs.h"

#include "core/accel/bvh_build.h"
#include "core/measure/comparison.h"
#include "core/traversal/observers.h"

namespace accelviz {

namespace {

/// The boxes by depth, and each triangle's leaf, read from the flat tree.
void describe_tree(const Bvh& bvh, uint32_t triangles, BvhTreeSummary& out) {
    out.boxes.assign(bvh.nodes.size(), {});
    out.leaf_of_triangle.assign(triangles, 0);
    for (size_t i = 0; i < bvh.nodes.size(); ++i) {
        const BvhNode& node = bvh.nodes[i];
        out.boxes[i].bounds = node.bounds;
        out.boxes[i].leaf = node.is_leaf();
        if (!node.is_leaf())
            for (uint32_t c : {node.first, node.first + 1}) out.boxes[c].depth = out.boxes[i].depth + 1;
    }
    uint32_t leaf = 0;
    for (const BvhNode& node : bvh.nodes) {
        if (!node.is_leaf()) continue;
        for (uint32_t k = node.first; k < node.first + node.count; ++k) out.leaf_of_triangle[bvh.prim_ids[k]] = leaf;
        ++leaf;
    }
}

}  // namespace

Expected<TwoBvhs> measure_two_bvhs(const Mesh& mesh, const Camera& camera, const BvhConfig& base,
                                   const std::array<BvhBuilder, 2>& builders, const TwoBvhsOptions& options) {
    TwoBvhs out;
    out.width = camera.width();
    out.height = camera.height();
    const std::vector<Ray> rays = comparison_rays(camera, options.sample_rays, options.seed);
    out.rays = rays.size();
    std::array<std::vector<Hit>, 2> hits;
    for (size_t i = 0; i < 2; ++i) {
        BvhConfig config = base;
        config.builder = builders[i];
        // Node indices do not depend on the threads (bvh_build.h), so neither does the picture.
        Expected<Bvh> built = build_bvh(mesh, config, nullptr, options.progress);
        if (!built) return Error{built.error()};
        Bvh& bvh = *built;
        bvh.traversal = options.traversal;
        BvhTreeSummary& tree = out.trees[i];
        tree.builder = builders[i];
        tree.stats = bvh.build_stats;
        describe_tree(bvh, mesh.triangle_count(), tree);
        Counters counters;
        uint64_t meeting_root = 0;
        for (size_t r = 0; r < rays.size(); ++r) {
            if (r % 256 == 0 && cancelled(options.progress)) return WorkProgress::cancelled_error();
            CountingObserver counter;
            hits[i].push_back(bvh.intersect_closest(rays[r], counter));
            if (counter.counters.nodes_visited == 0) continue;  // missed the root's box: no work in the tree
            ++meeting_root;
            counters += counter.counters;
        }
        out.rays_meeting_root = meeting_root;  // the same for both trees: one root box
        const double n = double(std::max<uint64_t>(1, meeting_root));
        tree.nodes_per_ray = double(counters.nodes_visited) / n;
        tree.box_tests_per_ray = double(counters.box_tests) / n;
        tree.triangle_tests_per_ray = double(counters.triangle_tests) / n;
    }
    for (size_t r = 0; r < rays.size(); ++r) {
        if (hits[0][r].found()) ++out.rays_that_hit;
        if (hits[0][r].tri != hits[1][r].tri || hits[0][r].t != hits[1][r].t) ++out.disagreements;
    }
    return out;
}

}  // namespace accelviz
