#pragma once
#include <vector>
/// The 3D view's camera on the GPU, following the camera contract
/// (core/render/camera.h) exactly, so that the window shows what the CPU ray
/// caster computes, pixel for pixel:
///   view = look-at(eye, target, up) with right = normalize(cross(forward, up)),
///          true_up = cross(right, forward)  (what glm::lookAt computes);
///   projection = perspective(vertical fov, aspect W/H of the view rectangle).
/// GL samples pixel centres (x + 0.5, y + 0.5), as the contract's rays do.

#include <array>

#include "core/math/aabb.h"
#include "core/render/camera.h"

namespace accelviz {

/// A rectangle of the framebuffer in pixels; y = 0 is the TOP row (as in
/// Image and ImGui), converted to GL's bottom-up rows where GL needs it.
struct ViewRect {
    int x = 0, y = 0, width = 0, height = 0;
    bool empty() const { return width <= 0 || height <= 0; }
    bool contains(double px, double py) const { return px >= x && py >= y && px < x + width && py < y + height; }
    bool operator==(const ViewRect&) const = default;
};

/// Everything a draw in the 3D view needs: camera, rectangle, clip planes.
struct View3D {
    CameraParams camera;
    ViewRect rect;
    double near_plane = 0.01;  ///< distance along `forward` of the near clip plane (> 0)
    double far_plane = 100.0;  ///< ... and of the far clip plane
    std::array<float, 16> view_projection{};  ///< column-major, as glUniformMatrix4fv wants it
};

/// Builds the view. The clip planes are fitted around `scene_bounds` (padded by 1%
/// of its diagonal) so the depth buffer's precision is spent on the scene; the
/// near plane stays at least far/1000 when the eye is inside the bounds.
View3D make_view3d(const CameraParams& camera, const ViewRect& rect, const Aabb& scene_bounds);

/// The ray distance t of the surface a depth-buffer value `window_depth` (in
/// [0, 1]) records at pixel (x, y) of the view rectangle (y = 0 top): undoes the
/// projection to the distance z along `forward`, then t = z * |forward + sx right
/// + sy true_up| for that pixel's contract ray. 1.0 (the clear value) gives +inf.
double depth_to_ray_t(const View3D& view, double window_depth, int x, int y);
/// The same for a whole depth image of the view rectangle (top row first).
std::vector<float> depth_image_to_ray_t(const View3D& view, const std::vector<float>& window_depth);
/// The inverse, for a ray cast of the view rectangle (top row first): the depth-buffer
/// value in [0, 1] of each pixel's hit distance t, so a ray-cast picture can fill
/// the z-buffer and what OpenGL draws after it is hidden behind the surface.
/// No hit (t = +inf) gives 1.0, the clear value; a hit nearer than the near plane, 0.
std::vector<float> ray_t_image_to_depth(const View3D& view, const std::vector<float>& ray_t);

}  // namespace accelviz
