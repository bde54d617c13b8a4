#pragma once
/// Helpers shared by the core tests.

#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "core/accel/factory.h"

namespace accelviz::test {

/// Path of a mesh in ../shared/assets (beside the repository).
inline std::string shared_asset(const std::string& name) {
    return std::string(ACCELVIZ_SHARED_ASSETS) + "/" + name;
}

inline bool shared_asset_exists(const std::string& name) {
    return std::filesystem::exists(shared_asset(name));
}

/// `type` with its default parameters over `mesh` (null, and a test failure, if it fails).
inline std::shared_ptr<const Accelerator> build_default(const Mesh& mesh, AccelType type) {
    AccelConfig config;
    config.type = type;
    auto accel = build_accelerator(mesh, config);
    EXPECT_TRUE(accel) << accel.error();
    return accel ? std::move(*accel) : nullptr;
}

}  // namespace accelviz::test
