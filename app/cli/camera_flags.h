#pragma once
/// The camera flags (--eye --target --up --fov) shared by every command that renders.

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "core/render/camera.h"

namespace accelviz::cli {

struct CameraFlags {
    std::string eye, target, up;
    std::optional<double> fov;

    void add_to(CLI::App& command);
    /// The camera the flags describe; flags not given take the scene's default view.
    Expected<CameraParams> resolve(const Aabb& scene_bounds) const;
};

/// "X,Y" -> two integers (the --pixel flag of trace and render --view step).
bool parse_pixel(const std::string& text, int& x, int& y);

}  // namespace accelviz::cli
