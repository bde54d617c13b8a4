#include "core/accel/wide_bvh.h"

#include <chrono>
#include <limits>

#include "core/accel/sah.h"

namespace accelviz {

nlohmann::json to_json(const WideBvhStats& stats) {
    return {{"width", stats.width},
            {"nodes", stats.nodes},
            {"leaves", stats.leaves},
            {"max_depth", stats.max_depth},
            {"avg_children", stats.avg_children},
            {"bytes_per_node", stats.bytes_per_node},
            {"sah_cost", stats.sah_cost},
            {"memory_bytes", stats.memory_bytes},
            {"collapse_ms", stats.collapse_ms},
            {"build_ms", stats.build_ms}};
}

template <int W, class Lanes>
nlohmann::json WideBvh<W, Lanes>::config() const {
    nlohmann::json j = to_json(build_config);
    j["traversal"] = to_string(traversal);
    j["triangle_test"] = to_string(triangle_test);
    return j;
}

template <int W, class Lanes>
nlohmann::json WideBvh<W, Lanes>::stats() const {
    nlohmann::json j = to_json(build_stats);
    j["binary"] = to_json(binary_stats);
    return j;
}

template <int W, class Lanes>
Expected<WideBvh<W, Lanes>> collapse_bvh_with(Bvh&& binary, WorkProgress* progress) {
    const auto start = std::chrono::steady_clock::now();
    using Node = WideBvhNode<W>;
    WideBvh<W, Lanes> wide;
    wide.build_config = binary.build_config;
    wide.build_config.width = W;
    wide.binary_stats = binary.build_stats;
    wide.traversal = binary.traversal;
    wide.triangle_test = binary.triangle_test;
    WideBvhStats& stats = wide.build_stats;
    stats.width = W;
    stats.bytes_per_node = sizeof(Node);
    stats.leaves = binary.build_stats.leaves;

    const auto& bin = binary.nodes;
    for (const BvhNode& n : bin)
        if (n.is_leaf() && n.count > std::numeric_limits<uint16_t>::max())
            return Error{"a BVH leaf of " + std::to_string(n.count) + " triangles is too large for a wide node (at most " +
                         std::to_string(std::numeric_limits<uint16_t>::max()) + ")"};

    const SahCostModel model{binary.build_config.cost_trav, binary.build_config.cost_isect};
    double sah = 0;
    uint64_t children = 0;
    if (!bin.empty()) {
        wide.root_bounds = bin[0].bounds;
        const float root_area = bin[0].bounds.area();
        auto p = [&](const Aabb& box) { return double(SahCostModel::hit_probability(box.area(), root_area)); };
        if (bin[0].is_leaf()) {
            wide.root_first = bin[0].first;
            wide.root_count = bin[0].count;
            sah = p(bin[0].bounds) * bin[0].count * model.cost_isect;
        } else {
            // Wide node `wide_id` is made of binary interior node `binary_id`, at `depth`.
            struct Work {
                uint32_t binary_id, wide_id, depth;
            };
            std::vector<Work> work{{0, 0, 0}};
            wide.nodes.reserve(bin.size() / (2 * (W - 1)) + 1);
            wide.nodes.emplace_back();
            while (!work.empty()) {
                const Work w = work.back();
                work.pop_back();
                if ((wide.nodes.size() & 4095) == 0 && cancelled(progress)) return WorkProgress::cancelled_error();
                sah += p(bin[w.binary_id].bounds) * model.cost_trav;

                // Open the interior child of largest area until there are W children (or only leaves).
                uint32_t child[W] = {bin[w.binary_id].first, bin[w.binary_id].first + 1};
                int n = 2;
                while (n < W) {
                    int widest = -1;
                    float widest_area = -1.0f;
                    for (int i = 0; i < n; ++i)
                        if (!bin[child[i]].is_leaf() && bin[child[i]].bounds.area() > widest_area) {
                            widest = i;
                            widest_area = bin[child[i]].bounds.area();
                        }
                    if (widest < 0) break;
                    const uint32_t opened = child[widest];
                    for (int i = n; i > widest + 1; --i) child[i] = child[i - 1];  // keep left-to-right order
                    child[widest] = bin[opened].first;
                    child[widest + 1] = bin[opened].first + 1;
                    ++n;
                }

                Node node;
                node.child_count = uint8_t(n);
                children += uint64_t(n);
                for (int i = 0; i < W; ++i) {
                    if (i >= n) {  // an empty lane: a box no ray enters, and the child count masks it anyway
                        node.boxes.set(i, Aabb{});
                        node.first[i] = 0;
                        node.count[i] = 0;
                        continue;
                    }
                    const BvhNode& c = bin[child[i]];
                    node.boxes.set(i, c.bounds);
                    if (c.is_leaf()) {
                        node.first[i] = c.first;
                        node.count[i] = uint16_t(c.count);
                        sah += p(c.bounds) * c.count * model.cost_isect;
                        stats.max_depth = std::max(stats.max_depth, w.depth + 1);
                    } else {
                        node.first[i] = uint32_t(wide.nodes.size());
                        node.count[i] = 0;
                        wide.nodes.emplace_back();
                        work.push_back({child[i], node.first[i], w.depth + 1});
                    }
                }
                wide.nodes[w.wide_id] = node;
            }
        }
    }
    stats.nodes = uint32_t(wide.nodes.size());
    stats.avg_children = stats.nodes ? double(children) / stats.nodes : 0.0;
    stats.sah_cost = sah;

    wide.prim_ids = std::move(binary.prim_ids);
    wide.triangles = std::move(binary.triangles);
    wide.corners = std::move(binary.corners);
    stats.memory_bytes = wide.nodes.size() * sizeof(Node) + wide.prim_ids.size() * sizeof(uint32_t) +
                         wide.triangles.size() * sizeof(Triangle) + wide.corners.size() * sizeof(TriangleCorners);
    stats.collapse_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    stats.build_ms = binary.build_stats.build_ms + stats.collapse_ms;
    return wide;
}

template <int W>
Expected<WideBvh<W>> collapse_bvh(Bvh&& binary, WorkProgress* progress) {
    return collapse_bvh_with<W, FastLanes<W>>(std::move(binary), progress);
}

template struct WideBvh<4>;
template struct WideBvh<8>;
template Expected<WideBvh<4>> collapse_bvh<4>(Bvh&&, WorkProgress*);
template Expected<WideBvh<8>> collapse_bvh<8>(Bvh&&, WorkProgress*);
// The scalar reference, where it is not already the fast one.
#if defined(__SSE2__)
template struct WideBvh<4, ScalarLanes<4>>;
template Expected<WideBvh<4, ScalarLanes<4>>> collapse_bvh_with<4, ScalarLanes<4>>(Bvh&&, WorkProgress*);
#endif
#if defined(__AVX__)
template struct WideBvh<8, ScalarLanes<8>>;
template Expected<WideBvh<8, ScalarLanes<8>>> collapse_bvh_with<8, ScalarLanes<8>>(Bvh&&, WorkProgress*);
#endif

ACCELVIZ_WIDE_TRAVERSALS(, 4)
ACCELVIZ_WIDE_TRAVERSALS(, 8)

}  // namespace accelviz
