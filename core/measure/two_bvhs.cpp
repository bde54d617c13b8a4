#include "core/measure/two_bvhs.h"

#include <optional>

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

Expected<BvhPair> build_bvh_pair(const Mesh& mesh, const BvhConfig& base, const std::array<BvhBuilder, 2>& builders,
                                 WorkProgress* progress) {
    std::array<std::optional<Bvh>, 2> built;
    for (size_t i = 0; i < 2; ++i) {
        BvhConfig config = base;
        config.builder = builders[i];
        // Node indices do not depend on the threads (bvh_build.h), so neither does the picture.
        Expected<Bvh> bvh = build_bvh(mesh, config, nullptr, progress);
        if (!bvh) return Error{bvh.error()};
        built[i] = std::move(*bvh);
    }
    return BvhPair{{std::move(*built[0]), std::move(*built[1])}};
}

Expected<TwoBvhs> measure_two_bvhs(const BvhPair& pair, const Mesh& mesh, const Camera& camera,
                                   const TwoBvhsOptions& options) {
    TwoBvhs out;
    out.width = camera.width();
    out.height = camera.height();
    const std::vector<Ray> rays = comparison_rays(camera, options.sample_rays, options.seed);
    out.rays = rays.size();
    std::array<std::vector<Hit>, 2> hits;
    for (size_t i = 0; i < 2; ++i) {
        Bvh const& built = pair.trees[i];
        BvhTreeSummary& tree = out.trees[i];
        tree.builder = built.build_config.builder;
        tree.stats = built.build_stats;
        describe_tree(built, mesh.triangle_count(), tree);
        Counters counters;
        uint64_t meeting_root = 0;
        for (size_t r = 0; r < rays.size(); ++r) {
            if (r % 256 == 0 && cancelled(options.progress)) return WorkProgress::cancelled_error();
            CountingObserver counter;
            hits[i].push_back(options.traversal == BvhTraversal::Ordered
                                  ? built.intersect_ordered(rays[r], counter)
                                  : built.intersect_unordered(rays[r], counter));
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

Expected<TwoBvhs> measure_two_bvhs(const Mesh& mesh, const Camera& camera, const BvhConfig& base,
                                   const std::array<BvhBuilder, 2>& builders, const TwoBvhsOptions& options) {
    auto pair = build_bvh_pair(mesh, base, builders, options.progress);
    if (!pair) return Error{pair.error()};
    return measure_two_bvhs(*pair, mesh, camera, options);
}

}  // namespace accelviz
