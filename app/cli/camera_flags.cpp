#include "app/cli/camera_flags.h"

#include <cstdio>

#include "app/cli/scene_input.h"
#include "core/geometry/scene.h"

namespace accelviz::cli {

void CameraFlags::add_to(CLI::App& command) {
    command.add_option("--eye", eye, "Camera position x,y,z (default: framed on the scene)");
    command.add_option("--target", target, "Point looked at x,y,z (default: scene centre)");
    command.add_option("--up", up, "Up vector x,y,z (default: 0,1,0)");
    command.add_option("--fov", fov, "Vertical field of view in degrees (default: 45)");
}

Expected<CameraParams> CameraFlags::resolve(const Aabb& scene_bounds) const {
    return resolve(default_camera(scene_bounds));
}

Expected<CameraParams> CameraFlags::resolve(CameraParams p) const {
    struct Field { const std::string& text; Vec3d& out; const char* flag; };
    for (Field f : {Field{eye, p.eye, "--eye"}, Field{target, p.target, "--target"}, Field{up, p.up, "--up"}}) {
        if (f.text.empty()) continue;
        auto v = parse_vec3(f.text);
        if (!v) return Error{std::string(f.flag) + ": " + v.error()};
        f.out = *v;
    }
    if (fov) p.fov_deg = *fov;
    if (auto err = validate(p)) return *err;
    return p;
}

bool parse_pixel(const std::string& text, int& x, int& y) {
    char rest = 0;
    return std::sscanf(text.c_str(), "%d,%d%c", &x, &y, &rest) == 2;
}

Expected<PixelRay> pixel_ray(const std::string& scene, const std::string& pixel, int width, int height,
                             const CameraFlags& camera) {
    PixelRay out;
    if (!parse_pixel(pixel, out.x, out.y)) return Error{"--pixel: expected X,Y (two integers), got '" + pixel + "'"};
    if (out.x < 0 || out.x >= width || out.y < 0 || out.y >= height)
        return Error{"--pixel " + pixel + " is outside the " + std::to_string(width) + "x" + std::to_string(height) +
                     " image"};
    auto mesh = load_scene_noting(scene, "trace");
    if (!mesh) return Error{mesh.error()};
    auto params = camera.resolve(mesh->bounds());
    if (!params) return Error{params.error()};
    out.mesh = std::move(*mesh);
    out.camera = *params;
    out.ray = Camera(out.camera, width, height).ray(out.x, out.y);
    return out;
}

}  // namespace accelviz::cli
