#pragma once
/// The lecture's slide "two BVHs over the same 22 triangles: which is better?":
/// two BVHs over one mesh, made by two builders with every other parameter the
/// same, and the figures that answer the question. The SAH cost is the expected
/// cost of a ray that meets the root's box (MacDonald & Booth 1990: each node
/// weighted by the chance S_node / S_root that such a ray meets it); nodes visited
/// and triangle tests per ray are measured over a seeded sample of the camera's
/// pixels, averaged over the rays that meet the root's box as the SAH cost is, so
/// they say what this view's rays pay once they reach the tree.

#include <array>
#include <cstdint>
#include <vector>

#include "core/accel/bvh.h"
#include "core/geometry/mesh.h"
#include "core/render/camera.h"
#include "core/util/expected.h"
#include "core/util/work_progress.h"

namespace accelviz {

/// One of the two trees: what to draw of it and what it costs.
struct BvhTreeSummary {
    BvhBuilder builder = BvhBuilder::SahBinned;
    BvhBuildStats stats;  ///< nodes, leaves, depth, SAH cost
    struct Box {
        Aabb bounds;
        uint32_t depth = 0;  ///< root = 0
        bool leaf = false;
    };
    std::vector<Box> boxes;                  ///< every node, in the tree's node order (root first)
    std::vector<uint32_t> leaf_of_triangle;  ///< [triangle id] = its leaf's number, counting leaves in node order
    // Per ray that meets the root's box:
    double nodes_per_ray = 0;  ///< nodes visited
    double box_tests_per_ray = 0;
    double triangle_tests_per_ray = 0;
};

struct TwoBvhs {
    std::array<BvhTreeSummary, 2> trees;
    int width = 0, height = 0;  ///< the image whose pixels the rays sample
    uint64_t rays = 0;             ///< rays traced through each tree
    uint64_t rays_meeting_root = 0;  ///< of them, rays that meet the root's box (the same box in both trees)
    uint64_t rays_that_hit = 0;    ///< of them, rays that hit a triangle
    /// Rays whose closest hit differs between the trees (0: both answer exactly, as
    /// they must; the panel says so).
    uint64_t disagreements = 0;
};

struct TwoBvhsOptions {
    uint64_t sample_rays = 4096;  ///< pixels sampled from the image (seeded; at most width x height)
    uint64_t seed = 1;
    BvhTraversal traversal = BvhTraversal::Ordered;  ///< the closest-hit algorithm the rays run
    WorkProgress* progress = nullptr;  ///< hears both builds (one stage each) and may cancel
};

/// The two trees, built once: a new camera only traces its rays through them again.
struct BvhPair {
    std::array<Bvh, 2> trees;
};

/// Builds `base` twice over `mesh`, once with each of `builders`. Errors: an invalid
/// config, or WorkProgress::cancelled_error().
Expected<BvhPair> build_bvh_pair(const Mesh& mesh, const BvhConfig& base, const std::array<BvhBuilder, 2>& builders,
                                 WorkProgress* progress = nullptr);

/// Traces the same sample of `camera`'s pixels (comparison_rays) through both trees of
/// `pair` (built over `mesh`). Errors: WorkProgress::cancelled_error().
Expected<TwoBvhs> measure_two_bvhs(const BvhPair& pair, const Mesh& mesh, const Camera& camera,
                                   const TwoBvhsOptions& options = {});

/// build_bvh_pair, then measure_two_bvhs.
Expected<TwoBvhs> measure_two_bvhs(const Mesh& mesh, const Camera& camera, const BvhConfig& base,
                                   const std::array<BvhBuilder, 2>& builders, const TwoBvhsOptions& options = {});

}  // namespace accelviz
