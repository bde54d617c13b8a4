#pragma once
/// Which acceleration structure: the lecture's naive O(N) test, the BVH, the
/// uniform grid, the KD tree, the octree and the BSP tree.

#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "core/util/enum_names.h"

namespace accelviz {

enum class AccelType { Naive, Bvh, Grid, Kd, Octree, Bsp };

inline constexpr EnumNames<AccelType, 6> kAccelTypeNames{{{
    {AccelType::Naive, "naive"},
    {AccelType::Bvh, "bvh"},
    {AccelType::Grid, "grid"},
    {AccelType::Kd, "kd"},
    {AccelType::Octree, "octree"},
    {AccelType::Bsp, "bsp"},
}}};

/// "naive", "bvh", "grid", "kd", "octree", "bsp".
constexpr std::string_view to_string(AccelType type) { return kAccelTypeNames.name(type); }
constexpr std::optional<AccelType> parse_accel_type(std::string_view name) { return kAccelTypeNames.parse(name); }
inline std::ostream& operator<<(std::ostream& out, AccelType type) { return out << to_string(type); }
/// The names, in menu order.
inline std::vector<std::string> accel_type_names() { return kAccelTypeNames.names(); }

}  // namespace accelviz
