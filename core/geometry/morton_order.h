#pragma once
/// Triangles in Morton (Z-curve) order of their centres: the order in which a
/// space-partitioning build reads them, so that the triangles of one cell lie near
/// each other in memory whatever order the file listed them in (a scan's triangles
/// often come in scan-line order; a mesh split or merged by a tool, in any order).
/// Morton 1966; for its use in building hierarchies, Lauterbach et al. 2009, "Fast
/// BVH construction on GPUs".

#include <cstdint>
#include <vector>

#include "core/geometry/mesh.h"

namespace accelviz {

/// The triangle ids ordered by the Morton code of their boxes' centres on a grid of
/// 2^10 cells per axis over `bounds`, ties by id. Deterministic (the codes in
/// parallel, then a radix sort).
std::vector<uint32_t> morton_order(const Mesh& mesh, const Aabb& bounds);

/// The Morton code of the cell (x, y, z), each below 2^10: their bits interleaved, x lowest.
uint32_t morton_code(uint32_t x, uint32_t y, uint32_t z);

}  // namespace accelviz
