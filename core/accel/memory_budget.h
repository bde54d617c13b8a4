#pragma once
/// The memory a build may take, decided before it starts: a configuration that
/// cannot fit the budget is refused with a message saying what to change, and the
/// structures whose size depends on the mesh (the grid's and the trees' references)
/// get caps that keep them inside it. So a build never ends in the system's
/// out-of-memory kill, in front of a class, with the scene gone.
///
/// The estimates are upper bounds from the sizes of what each build allocates (the
/// structure's arrays and the build's scratch); docs/performance.md compares them
/// with measured peaks.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "core/accel/factory.h"
#include "core/util/expected.h"

namespace accelviz {

/// Half of the machine's physical memory (the default budget; 4 GiB if unknown).
uint64_t default_memory_budget();

/// "512 MB", "3.1 GB": a byte count for messages.
std::string format_bytes(uint64_t bytes);

/// "12G", "512M", "64K", "1.5G" or a plain byte count, as --memory-budget takes it.
std::optional<uint64_t> parse_memory_size(std::string_view text);

/// The bytes a build of `config.type` over `triangles` triangles takes at most for
/// what does not depend on how many references it makes (for naive and the BVH:
/// all of it).
uint64_t fixed_build_bytes(const AccelConfig& config, uint64_t triangles);

/// The bytes each triangle reference costs the grid, KD tree and octree builds at
/// most (ids, scratch and the leaf-order triangle copies); 0 for naive and the BVH.
uint64_t bytes_per_reference(const AccelConfig& config);

/// `config` made to fit `budget` bytes (0: default_memory_budget()) over `triangles`
/// triangles: the grid's reference cap and the trees' duplication budget lowered
/// where the budget asks for it (with `note` saying so), or a one-line error naming
/// the flag to change when even the fixed part does not fit.
Expected<AccelConfig> fit_memory_budget(const AccelConfig& config, uint64_t triangles, uint64_t budget,
                                        std::string* note);

}  // namespace accelviz
