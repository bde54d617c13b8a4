#pragma once
/// The camera flags (--eye --target --up --fov) shared by every command that renders.

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "core/geometry/mesh.h"
#include "core/render/camera.h"

namespace accelviz::cli {

struct CameraFlags {
    std::string eye, target, up;
    std::optional<double> fov;

    void add_to(CLI::App& command);
    /// The camera the flags describe; flags not given take the scene's default view.
    Expected<CameraParams> resolve(const Aabb& scene_bounds) const;
    /// The same over another starting camera (a preset's): flags given replace its fields.
    Expected<CameraParams> resolve(CameraParams base) const;
    /// True when at least one camera flag was given.
    bool any() const { return !eye.empty() || !target.empty() || !up.empty() || fov.has_value(); }
};

/// "X,Y" -> two integers (the --pixel flag of trace and render --view step).
bool parse_pixel(const std::string& text, int& x, int& y);

/// The ray of one pixel of a width x height image (trace, render --view step): the
/// scene loaded, the camera the flags describe over it, and the pixel's ray.
struct PixelRay {
    Mesh mesh;
    CameraParams camera;
    int x = 0, y = 0;
    Ray ray;
};
/// `pixel` ("X,Y") checked against the image, `scene` loaded, the camera resolved;
/// errors are one line naming the flag or the file.
Expected<PixelRay> pixel_ray(const std::string& scene, const std::string& pixel, int width, int height,
                             const CameraFlags& camera);

}  // namespace accelviz::cli
