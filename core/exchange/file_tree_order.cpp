#include "core/exchange/file_tree_order.h"

#include <algorithm>
#include <span>

#include "core/accel/sah.h"

namespace accelviz {

namespace {

/// The children a node names, those that are nodes of the file.
std::vector<uint64_t> children_of(const StructureFile& file, uint64_t node) {
    std::vector<uint64_t> out;
    if (file.type == AccelType::Bvh) {
        const FileBvhNode& n = file.bvh_nodes[node];
        if (!n.interior) return out;
        for (uint32_t c : n.children)
            if (c < file.bvh_nodes.size()) out.push_back(c);
    } else {
        const FileKdNode& n = file.kd_nodes[node];
        if (n.is_leaf()) return out;
        for (uint32_t c : n.children)
            if (c < file.kd_nodes.size()) out.push_back(c);
    }
    return out;
}

bool is_leaf(const StructureFile& file, uint64_t node) {
    return file.type == AccelType::Bvh ? !file.bvh_nodes[node].interior : file.kd_nodes[node].is_leaf();
}

/// A leaf's triangle ids as the file gives them (a BVH leaf's range clipped to "order").
std::span<const uint32_t> leaf_triangles(const StructureFile& file, uint64_t node) {
    if (file.type == AccelType::Kd) return file.kd_nodes[node].triangles;
    const FileBvhNode& n = file.bvh_nodes[node];
    const uint64_t size = file.order.size();
    const uint64_t first = std::min(n.first, size);
    const uint64_t count = std::min(n.count, size - first);
    return std::span<const uint32_t>(file.order).subspan(first, count);
}

}  // namespace

FileTreeOrder file_tree_order(const StructureFile& file) {
    FileTreeOrder order;
    const size_t count = file.type == AccelType::Bvh  ? file.bvh_nodes.size()
                         : file.type == AccelType::Kd ? file.kd_nodes.size()
                                                      : 0;
    order.parent.assign(count, -1);
    order.depth.assign(count, 0);
    order.reached.assign(count, 0);
    if (count == 0) return order;
    order.reached[0] = 1;
    std::vector<uint64_t> queue = {0};  // breadth first: the first parent to name a node is its parent
    for (size_t q = 0; q < queue.size(); ++q) {
        const uint64_t i = queue[q];
        for (uint64_t c : children_of(file, i)) {
            if (order.reached[c]) continue;
            order.reached[c] = 1;
            order.parent[c] = int64_t(i);
            order.depth[c] = order.depth[i] + 1;
            queue.push_back(c);
        }
    }
    if (file.type == AccelType::Kd) order.kd_cells = file_kd_cells(file);
    return order;
}

FileNodeStep file_node_step(const StructureFile& file, const FileTreeOrder& order, uint64_t node,
                            size_t mesh_triangles, SahCosts costs) {
    FileNodeStep step;
    step.node = node;
    if (node >= order.size()) return step;
    if (order.parent[node] >= 0) step.parent = uint64_t(order.parent[node]);
    step.depth = order.depth[node];
    step.reached = order.reached[node] != 0;
    step.leaf = is_leaf(file, node);
    const bool kd = file.type == AccelType::Kd;
    step.box = kd ? order.kd_cells[node] : file.bvh_nodes[node].box;
    if (kd && !step.leaf) {
        step.axis = file.kd_nodes[node].axis;
        step.split = file.kd_nodes[node].split;
    }

    // Triangles under a node: every leaf below it, each node walked once (a file
    // may name a node twice, or in a cycle), each triangle listed once per subtree
    // (a KD tree lists a triangle in every cell it touches).
    std::vector<uint8_t> walked(order.size(), 0);
    std::vector<uint64_t> touched_nodes;
    std::vector<uint32_t> stamp(mesh_triangles, 0);  // which list a triangle is in already
    uint32_t list = 0;
    auto triangles_under = [&](uint64_t top) {
        ++list;
        std::vector<uint32_t> out;
        std::vector<uint64_t> stack = {top};
        while (!stack.empty()) {
            const uint64_t i = stack.back();
            stack.pop_back();
            if (walked[i]) continue;
            walked[i] = 1;
            touched_nodes.push_back(i);
            if (!is_leaf(file, i)) {
                for (uint64_t c : children_of(file, i)) stack.push_back(c);
                continue;
            }
            for (uint32_t t : leaf_triangles(file, i))
                if (t < mesh_triangles && stamp[t] != list) {
                    stamp[t] = list;
                    out.push_back(t);
                }
        }
        for (uint64_t i : touched_nodes) walked[i] = 0;  // the next child walks its own subtree
        touched_nodes.clear();
        return out;
    };

    const SahCostModel model{costs.trav, costs.isect};
    if (step.leaf) {
        step.triangles.push_back(triangles_under(node));
        step.triangle_count = step.triangles[0].size();
        step.leaf_cost = step.split_cost = model.leaf_cost(uint32_t(step.triangle_count));
        return step;
    }
    step.children = children_of(file, node);
    if (step.children.size() > size_t(kStructureMaxArity)) {
        // Not valid (check says so); a node of thousands of children would stall the view.
        step.children_left_out = step.children.size() - size_t(kStructureMaxArity);
        step.children.resize(size_t(kStructureMaxArity));
    }
    const float area = step.box.area();
    step.split_cost = costs.trav;
    for (size_t k = 0; k < step.children.size(); ++k) {
        const uint64_t c = step.children[k];
        step.child_boxes.push_back(kd ? order.kd_cells[c] : file.bvh_nodes[c].box);
        step.triangles.push_back(c == node ? std::vector<uint32_t>{} : triangles_under(c));
        const float p = SahCostModel::hit_probability(step.child_boxes.back().area(), area);
        step.child_probability.push_back(p);
        step.split_cost += p * float(step.triangles.back().size()) * costs.isect;
    }
    // The node's own count: its children's lists together, each triangle once.
    ++list;
    for (const auto& under : step.triangles)
        for (uint32_t t : under)
            if (stamp[t] != list) {
                stamp[t] = list;
                ++step.triangle_count;
            }
    step.leaf_cost = model.leaf_cost(uint32_t(step.triangle_count));
    return step;
}

}  // namespace accelviz
