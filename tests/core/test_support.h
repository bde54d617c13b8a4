#pragma once
/// Helpers shared by the core tests.

#include <filesystem>
#include <string>

namespace accelviz::test {

/// Path of a mesh in ../shared/assets (beside the repository).
inline std::string shared_asset(const std::string& name) {
    return std::string(ACCELVIZ_SHARED_ASSETS) + "/" + name;
}

inline bool shared_asset_exists(const std::string& name) {
    return std::filesystem::exists(shared_asset(name));
}

}  // namespace accelviz::test
