#pragma once
/// The exchange format for acceleration structures: a BVH (2 to 8 children per
/// node), a KD tree or a uniform grid over a mesh, as plain data that any language
/// can write. Students build their own trees (in Python, C++, ...), write them in
/// this format, and `accelviz check` says whether they are valid and how good they
/// are; `accelviz export` writes ours the same way. docs/structure-format.md
/// defines the format; this is its reader and writer, and nothing here trusts what
/// it reads: structure_check.h judges it.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/mesh.h"
#include "core/math/aabb.h"
#include "core/util/expected.h"

namespace accelviz {

inline constexpr int kStructureFormatVersion = 1;
inline constexpr int kStructureMaxArity = 8;

/// The mesh a structure was built over: its triangles are numbered 0..triangles-1
/// in the order accelviz reads them (faces in file order, polygons split as fans).
struct MeshReference {
    std::string path;               ///< as the writer gave it (informative: check is given the mesh)
    uint64_t triangles = 0;
    std::optional<uint32_t> crc32;  ///< mesh_crc32 of the mesh; absent: not checked
};

/// A BVH node. Interior: `children` lists 1.. node indices (valid: 2 to 8). Leaf:
/// the triangles order[first .. first + count) of the file's triangle order.
struct FileBvhNode {
    Aabb box;
    bool interior = false;
    std::vector<uint32_t> children;
    uint64_t first = 0, count = 0;
};

/// A KD tree node. Interior: split plane `split` on `axis` (0, 1, 2), children[0]
/// below the plane, children[1] above. Leaf (axis < 0): the triangles listed.
struct FileKdNode {
    int axis = -1;
    float split = 0;
    std::array<uint32_t, 2> children{};
    std::vector<uint32_t> triangles;
    bool is_leaf() const { return axis < 0; }
};

/// A uniform grid's non-empty cell: (x, y, z) with x fastest, and its triangles.
struct FileGridCell {
    std::array<uint32_t, 3> cell{};
    std::vector<uint32_t> triangles;
};

/// A structure as read from a file (not yet checked) or exported from ours.
/// Node 0 is the root of a tree.
struct StructureFile {
    AccelType type = AccelType::Bvh;  ///< Bvh, Kd or Grid
    MeshReference mesh;
    std::string builder;  ///< who or what built it (free text, optional)
    // Bvh
    std::vector<FileBvhNode> bvh_nodes;
    std::vector<uint32_t> order;  ///< the triangle ids the BVH leaves' ranges index
    // Kd
    std::vector<FileKdNode> kd_nodes;
    // Kd and Grid
    Aabb bounds;
    // Grid
    std::array<uint32_t, 3> resolution{};
    std::vector<FileGridCell> cells;

    /// Children per interior BVH node at most (0 without interior nodes).
    int max_arity() const;
};

/// The JSON text of the format (compact: one node per line).
std::string structure_json(const StructureFile& file);
/// Reads the JSON text; errors name what is malformed ("node 12: \"box\" must be 6
/// numbers"). Structural faults (a child index out of range, a cycle, ...) are not
/// errors here: check_structure reports them.
Expected<StructureFile> parse_structure_json(const std::string& text);

/// The compact binary variant (docs/structure-format.md): the same fields,
/// little-endian, for trees too big for JSON.
std::string structure_binary(const StructureFile& file);
Expected<StructureFile> parse_structure_binary(const std::string& bytes);

/// Whether `path` looks like a structure file (the binary magic, or "accelviz-structure"
/// in its first 4 KiB): how the window tells a dropped tree from a dropped mesh.
bool looks_like_structure_file(const std::string& path);

/// Reads `path`: binary if it starts with the binary variant's magic, else JSON.
/// Errors start with the path.
Expected<StructureFile> read_structure_file(const std::string& path);
/// Writes binary when the path ends in ".avs", else JSON. Errors name the path.
std::optional<Error> write_structure_file(const StructureFile& file, const std::string& path);

/// Our structure `accel` over `mesh` in the exchange format: a BVH of any width, a
/// KD tree or a grid (naive and octree: an error). Triangle ids are the mesh's.
Expected<StructureFile> export_structure(const Accelerator& accel, const Mesh& mesh, MeshReference reference);

/// The checksum a structure file names its mesh by: CRC-32 (the zlib one) of the
/// OBJ file's bytes; for a built-in scene ("builtin:..."), of its triangles' corner
/// positions as little-endian float32, 9 per triangle. Errors: the file unreadable.
Expected<uint32_t> mesh_crc32(const std::string& source, const Mesh& mesh);

}  // namespace accelviz
