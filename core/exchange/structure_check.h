#pragma once
/// Judging a structure from a file (structure_file.h): is it a valid BVH, KD tree
/// or grid over this mesh, and if so, how good is it. The questions students ask
/// of their own trees: is my tree valid, why is it slow, where does my traversal
/// go wrong. Valid means that our traversal through it finds the same closest hit
/// as brute force for every ray; the checks below are what that needs.

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/exchange/structure_file.h"

namespace accelviz {

/// One thing wrong, in plain words. `node`: the node (BVH, KD) or cell entry
/// (grid) it is about; none for the structure as a whole.
struct StructureProblem {
    std::optional<uint64_t> node;
    std::string message;
};

struct StructureCheck {
    std::vector<StructureProblem> problems;  ///< the first max_listed ones
    uint64_t problem_count = 0;              ///< all of them
    std::vector<uint64_t> bad_nodes;         ///< every node a problem is about (and a box's parent), sorted, once: what the window draws red
    bool valid() const { return problem_count == 0; }
};

/// How far a box may stick out of the box that should hold it, for the structure's
/// scene: 1e-6 of the mesh's largest extent (a writer's rounding, not a fault).
float containment_tolerance(const Mesh& mesh);

/// Every check of docs/structure-format.md ("What check checks"): the mesh named
/// (triangle count, and the checksum when both sides have one: `mesh_crc`), node
/// indices in range, a tree (no cycles, no node with two parents, every node
/// reachable), 2 to 8 children per BVH interior node and no empty leaves, boxes
/// that are boxes, each child box inside its parent's (the amount it sticks out),
/// every triangle in exactly one BVH leaf and inside that leaf's box, a KD
/// triangle in every leaf cell it overlaps or touches (within the tolerance: a ray
/// that hits it on the cell's face must find it there), grid cells in range and
/// each triangle in every cell it overlaps or touches; and what our traversal needs (depth, leaf sizes).
StructureCheck check_structure(const StructureFile& file, const Mesh& mesh, std::optional<uint32_t> mesh_crc,
                               size_t max_listed = 50);

/// Every KD node's cell in a file's tree: the root's is the bounds, a child's its
/// parent's cut at the parent's plane (the lower child below it). Safe on a file that
/// is not a tree: each node gets the cell of the first parent that reaches it, and a
/// node no parent reaches the bounds.
std::vector<Aabb> file_kd_cells(const StructureFile& file);

/// Our traversal over a valid structure from a file: a BVH of arity 2 as a Bvh, up
/// to 4 or 8 as a WideBvh<4> / <8>, a KD tree as a KdTree, a grid as a UniformGrid.
/// Errors: the file is not valid (check_structure first).
Expected<std::shared_ptr<const Accelerator>> structure_accelerator(const StructureFile& file, const Mesh& mesh);

/// A structure's figures: its shape, its SAH cost, and what our traversal does
/// through it on a set of rays.
struct StructureFigures {
    uint64_t nodes = 0, interior = 0, leaves = 0, empty_leaves = 0;
    uint32_t depth = 0;             ///< deepest leaf; the root at 0
    double avg_children = 0;        ///< per interior node
    double references = 0;          ///< Σ leaf sizes / triangles (1 for a BVH, more where triangles are in several cells)
    double sah_cost = 0;            ///< Σ interior A/A_root·C_trav + Σ leaf A/A_root·n·C_isect (grid: per cell)
    std::vector<uint64_t> leaf_sizes;  ///< [k] = leaves (cells: non-empty cells) holding k triangles
    uint64_t rays = 0;
    double nodes_per_ray = 0, box_tests_per_ray = 0, triangle_tests_per_ray = 0;
    uint64_t mismatches = 0;        ///< rays whose closest hit differs from the reference's (0 when exact)
};

struct SahCosts {
    float trav = 1.0f;   ///< C_trav
    float isect = 1.0f;  ///< C_isect
};

/// The shape and SAH cost of a valid `file`, and, through `accel`
/// (structure_accelerator of it), the work per ray on `rays`; `reference` gives the
/// right closest hits (our own BVH: exact against brute force) to count mismatches.
StructureFigures measure_structure(const StructureFile& file, const Mesh& mesh, const Accelerator& accel,
                                   std::span<const Ray> rays, const Accelerator& reference, SahCosts costs);

}  // namespace accelviz

namespace accelviz {

/// A structure file read and checked over `mesh`, and, when it is valid, laid out for
/// our traversal: what the window loads (it draws an invalid file's nodes, the faulty
/// ones red). `mesh_crc`: the mesh's checksum, when known, to check the file's against.
struct CheckedStructureFile {
    std::shared_ptr<const StructureFile> file;
    StructureCheck check;
    std::shared_ptr<const Accelerator> accel;  ///< null when the file is not valid
};
Expected<CheckedStructureFile> read_and_check_structure(const std::string& path, const Mesh& mesh,
                                                        std::optional<uint32_t> mesh_crc, size_t max_listed = 50);

/// read_and_check_structure, with `source` (the mesh's OBJ path or built-in name;
/// empty: not checked) naming the mesh for its checksum; an invalid file is an error
/// with its first problem (accelviz check lists all): `trace --structure` and every
/// command's `--structure`.
Expected<std::shared_ptr<const Accelerator>> load_structure_file(const std::string& path, const Mesh& mesh,
                                                                 const std::string& source);

}  // namespace accelviz
