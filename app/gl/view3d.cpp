#include "app/gl/view3d.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/mat4x4.hpp>

namespace accelviz {

namespace {

glm::dvec3 to_glm(Vec3d v) { return {v.x, v.y, v.z}; }

}  // namespace

View3D make_view3d(const CameraParams& camera, const ViewRect& rect, const Aabb& scene_bounds) {
    View3D view;
    view.camera = camera;
    view.rect = rect;

    const Vec3d forward = normalize(camera.target - camera.eye);
    if (!scene_bounds.empty()) {
        // Distances along `forward` of the 8 corners of the (padded) bounds.
        const Vec3d lo = to_double(scene_bounds.lo), hi = to_double(scene_bounds.hi);
        const Vec3d diagonal = hi - lo;
        const double pad = 0.01 * std::sqrt(dot(diagonal, diagonal)) + 1e-6;
        double z_min = std::numeric_limits<double>::infinity(), z_max = -z_min;
        for (int corner = 0; corner < 8; ++corner) {
            const Vec3d p{(corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z};
            const double z = dot(p - camera.eye, forward);
            z_min = std::min(z_min, z);
            z_max = std::max(z_max, z);
        }
        if (z_max + pad > 0) {
            view.far_plane = z_max + pad;
            view.near_plane = std::max(z_min - pad, view.far_plane / 1000.0);
        }
    }

    const double aspect = rect.height > 0 ? double(rect.width) / rect.height : 1.0;
    const glm::dmat4 look = glm::lookAt(to_glm(camera.eye), to_glm(camera.target), to_glm(camera.up));
    const glm::dmat4 projection =
        glm::perspective(glm::radians(camera.fov_deg), aspect, view.near_plane, view.far_plane);
    const glm::dmat4 vp = projection * look;
    for (int column = 0; column < 4; ++column)
        for (int row = 0; row < 4; ++row) view.view_projection[size_t(column * 4 + row)] = float(vp[column][row]);
    return view;
}

namespace {

double depth_to_ray_t(const View3D& view, const Camera& camera, double window_depth, int x, int y) {
    if (window_depth >= 1.0) return std::numeric_limits<double>::infinity();
    const double n = view.near_plane, f = view.far_plane;
    const double z_ndc = 2.0 * window_depth - 1.0;
    const double z = 2.0 * n * f / ((f + n) - z_ndc * (f - n));  // distance along forward
    const Vec3d d = camera.plane_direction(x + 0.5, y + 0.5);  // forward component is exactly 1
    return z * std::sqrt(dot(d, d));
}

}  // namespace

double depth_to_ray_t(const View3D& view, double window_depth, int x, int y) {
    return depth_to_ray_t(view, Camera(view.camera, view.rect.width, view.rect.height), window_depth, x, y);
}

std::vector<float> depth_image_to_ray_t(const View3D& view, const std::vector<float>& window_depth) {
    const int w = view.rect.width, h = view.rect.height;
    const Camera camera(view.camera, w, h);
    std::vector<float> t(window_depth.size(), std::numeric_limits<float>::infinity());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = size_t(y) * w + x;
            if (i < window_depth.size()) t[i] = float(depth_to_ray_t(view, camera, window_depth[i], x, y));
        }
    return t;
}

std::vector<float> ray_t_image_to_depth(const View3D& view, const std::vector<float>& ray_t) {
    const int w = view.rect.width, h = view.rect.height;
    const Camera camera(view.camera, w, h);
    const double n = view.near_plane, f = view.far_plane;
    std::vector<float> depth(ray_t.size(), 1.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = size_t(y) * w + x;
            if (i >= ray_t.size() || !std::isfinite(ray_t[i])) continue;
            const Vec3d d = camera.plane_direction(x + 0.5, y + 0.5);  // forward component is exactly 1
            const double z = ray_t[i] / std::sqrt(dot(d, d));           // distance along forward
            // glm::perspective's depth: z_ndc = ((f + n) - 2 n f / z) / (f - n).
            const double z_ndc = ((f + n) - 2.0 * n * f / std::max(z, n)) / (f - n);
            depth[i] = float(std::clamp(0.5 * z_ndc + 0.5, 0.0, 1.0));
        }
    return depth;
}

}  // namespace accelviz
