#include "core/accel/wide_bvh.h"

#include <chrono>
#include <limits>

#include <tbb/parallel_for.h>

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
void WideBvh<W, Lanes>::make_leaf_lanes(const TriangleArray& leaf_order_triangles) {
    leaf_lanes.resize(leaf_order_triangles.size());
    auto fill = [&](uint32_t first, uint32_t count) {
        for (uint32_t j = 0; j < count; ++j) leaf_lanes.set(first, count, j, leaf_order_triangles[first + j]);
    };
    if (root_count > 0) fill(root_first, root_count);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, nodes.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t n = r.begin(); n < r.end(); ++n)
            for (int i = 0; i < nodes[n].child_count; ++i)
                if (nodes[n].is_leaf(i)) fill(nodes[n].first[i], nodes[n].count[i]);
    });
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

    const auto& bin = binary.nodes;
    constexpr uint32_t kMaxLeaf = std::numeric_limits<uint16_t>::max();
    for (const BvhNode& n : bin)
        if (n.is_leaf() && n.count > kMaxLeaf)
            return Error{"a BVH leaf of " + std::to_string(n.count) + " triangles is too large for a wide node (at most " +
                         std::to_string(kMaxLeaf) + ")"};

    const SahCostModel model = binary.build_config.sah_model();
    if (!bin.empty()) {
        auto is_leaf = [&](uint32_t n) { return bin[n].is_leaf(); };
        auto area = [&](uint32_t n) { return bin[n].bounds.area(); };
        const float root_area = area(0);
        auto p = [&](uint32_t n) { return double(SahCostModel::hit_probability(area(n), root_area)); };
        wide.root_bounds = bin[0].bounds;
        double sah = 0;
        if (is_leaf(0)) {
            wide.root_first = bin[0].first;
            wide.root_count = bin[0].count;
            sah = p(0) * model.tests(bin[0].count) * model.cost_isect;
            stats.leaves = 1;
        } else {
            // Pass 1: each wide node's children (binary node ids), wide nodes numbered
            // depth first with a node's interior children consecutive.
            struct Children {
                uint32_t binary[W];
                uint32_t wide[W];  ///< an interior child's wide node; UINT32_MAX for a leaf
                uint32_t n = 0;
            };
            struct Work {
                uint32_t binary_id, wide_id, depth;
            };
            std::vector<Children, LargeArrayAllocator<Children>> lists(1);
            lists.reserve(bin.size() / 2 + 1);  // at most one wide node per binary interior node
            std::vector<Work> work{{0, 0, 0}};
            uint64_t children = 0;
            for (uint32_t listed = 0; !work.empty(); ++listed) {
                const Work w = work.back();
                work.pop_back();
                if ((listed & 1023) == 0 && cancelled(progress)) return WorkProgress::cancelled_error();
                sah += p(w.binary_id) * model.cost_trav;
                // Open the interior child of largest area until there are W children (or only leaves).
                Children c;
                c.binary[0] = bin[w.binary_id].first;
                c.binary[1] = bin[w.binary_id].first + 1;
                c.n = 2;
                while (c.n < W) {
                    int widest = -1;
                    float widest_area = -1.0f;
                    for (int i = 0; i < int(c.n); ++i)
                        if (area(c.binary[i]) > widest_area && !is_leaf(c.binary[i])) {
                            widest = i;
                            widest_area = area(c.binary[i]);
                        }
                    if (widest < 0) break;
                    const uint32_t opened = c.binary[widest];
                    for (int i = int(c.n); i > widest + 1; --i) c.binary[i] = c.binary[i - 1];  // keep left-to-right order
                    c.binary[widest] = bin[opened].first;
                    c.binary[widest + 1] = bin[opened].first + 1;
                    ++c.n;
                }
                children += c.n;
                for (uint32_t i = 0; i < c.n; ++i) {
                    const uint32_t b = c.binary[i];
                    if (is_leaf(b)) {
                        c.wide[i] = UINT32_MAX;
                        sah += p(b) * model.tests(bin[b].count) * model.cost_isect;
                        stats.max_depth = std::max(stats.max_depth, w.depth + 1);
                        ++stats.leaves;
                    } else {
                        c.wide[i] = uint32_t(lists.size());
                        lists.emplace_back();
                        work.push_back({b, c.wide[i], w.depth + 1});
                    }
                }
                lists[w.wide_id] = c;
            }
            stats.avg_children = double(children) / double(lists.size());

            // Pass 2: the nodes, each from its list, in parallel.
            wide.nodes.resize(lists.size());
            tbb::parallel_for(tbb::blocked_range<size_t>(0, lists.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
                if (cancelled(progress)) return;
                for (size_t k = r.begin(); k < r.end(); ++k) {
                    const Children& c = lists[k];
                    Node& node = wide.nodes[k];
                    node.child_count = uint8_t(c.n);
                    for (int i = 0; i < W; ++i) {
                        if (i >= int(c.n)) {  // an empty lane: a box no ray enters, and the child count masks it anyway
                            node.boxes.set(i, Aabb{});
                            node.first[i] = 0;
                            node.count[i] = 0;
                            continue;
                        }
                        const uint32_t b = c.binary[i];
                        node.boxes.set(i, bin[b].bounds);
                        const bool leaf = c.wide[i] == UINT32_MAX;
                        node.first[i] = leaf ? bin[b].first : c.wide[i];
                        node.count[i] = leaf ? uint16_t(bin[b].count) : uint16_t(0);
                    }
                }
            });
            if (cancelled(progress)) return WorkProgress::cancelled_error();
        }
        stats.sah_cost = sah;
    }
    stats.nodes = uint32_t(wide.nodes.size());

    wide.prim_ids = std::move(binary.prim_ids);
    wide.corners = std::move(binary.corners);
    wide.make_leaf_lanes(binary.triangles);
    binary.triangles = {};
    // As the binary tree counts it: nodes, ids and triangles (not the watertight test's corners).
    stats.memory_bytes = wide.nodes.size() * sizeof(Node) + wide.prim_ids.size() * sizeof(uint32_t) +
                         wide.leaf_lanes.memory_bytes();
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
