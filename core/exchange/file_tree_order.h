#pragma once
/// The construction-order view of a tree from a file (a student's BVH or KD tree):
/// its nodes one at a time, in the order the file numbers them. A builder that
/// writes each node as it makes it (the usual recursive build: a node, then its
/// first child's subtree, then the next) numbers them in construction order, so
/// stepping by node index replays the student's build split by split, as the
/// construction stepper replays ours: the node's box (a KD node's cell), its
/// children's boxes and the triangles that went to each, and what the split costs
/// by the SAH (lecture: C = C_trav + S_A/S_N N_A C_isect + S_B/S_N N_B C_isect).
///
/// Plain data for the window. Nothing here trusts the file: on a file that is not
/// a valid tree (check_structure says what is wrong) indices out of range are left
/// out, a node is walked once however many parents name it, and a cycle ends.

#include <cstdint>
#include <optional>
#include <vector>

#include "core/exchange/structure_check.h"
#include "core/exchange/structure_file.h"
#include "core/math/aabb.h"

namespace accelviz {

/// Who reaches whom in a file's BVH or KD tree: computed once per file.
struct FileTreeOrder {
    std::vector<int64_t> parent;      ///< the first node (breadth first from the root) naming it; -1: none
    std::vector<uint32_t> depth;      ///< the root's 0 (and a node no one reaches)
    std::vector<uint8_t> reached;     ///< 1: reached from the root (node 0)
    std::vector<Aabb> kd_cells;       ///< KD: every node's cell (file_kd_cells)
    size_t size() const { return parent.size(); }
};

/// The order of `file`'s nodes; empty for a grid.
FileTreeOrder file_tree_order(const StructureFile& file);

/// One node of a file's tree, as the construction-order view shows it.
struct FileNodeStep {
    uint64_t node = 0;
    std::optional<uint64_t> parent;
    uint32_t depth = 0;
    bool reached = true;              ///< false: no path from the root leads here
    bool leaf = true;
    Aabb box;                         ///< BVH: the node's box; KD: its cell
    int axis = -1;                    ///< KD interior: the split plane's axis (0 x, 1 y, 2 z)
    float split = 0;                  ///< KD interior: the split plane's position
    std::vector<uint64_t> children;   ///< interior: as the file lists them (those in range, at most kStructureMaxArity)
    uint64_t children_left_out = 0;   ///< children beyond kStructureMaxArity (a file that is not valid)
    std::vector<Aabb> child_boxes;    ///< BVH: the children's boxes; KD: their cells (below, above)
    /// Interior: the triangles under each child (from every leaf below it, each
    /// once); a leaf: one list, its own. Ids that are not the mesh's are left out.
    std::vector<std::vector<uint32_t>> triangles;
    uint64_t triangle_count = 0;      ///< different triangles under the node
    std::vector<float> child_probability;  ///< S_child / S_node: the SAH's chance a ray through the node meets the child
    float leaf_cost = 0;              ///< N · C_isect
    float split_cost = 0;             ///< interior: C_trav + Σ S_c/S_N · N_c · C_isect (a leaf: its leaf cost)
};

/// Node `node` (< order.size()) of `file` over a mesh of `mesh_triangles` triangles.
/// Walks the node's subtree (and clears a mark per node and per triangle of the
/// whole tree and mesh). Of a node naming more than kStructureMaxArity children
/// (not valid) only the first that many are walked.
FileNodeStep file_node_step(const StructureFile& file, const FileTreeOrder& order, uint64_t node,
                            size_t mesh_triangles, SahCosts costs);

}  // namespace accelviz
