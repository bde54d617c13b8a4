#include "app/gui/camera_control.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

namespace accelviz {

namespace {

double length(Vec3d v) { return std::sqrt(dot(v, v)); }

/// Rodrigues' rotation of v about the unit axis k by `angle` radians.
Vec3d rotate(Vec3d v, Vec3d k, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return v * c + cross(k, v) * s + k * (dot(k, v) * (1 - c));
}

}  // namespace

void orbit(CameraParams& camera, double yaw, double pitch) {
    const Vec3d up = normalize(camera.up);
    Vec3d offset = camera.eye - camera.target;  // target -> eye
    const double distance = length(offset);
    if (distance == 0) return;
    offset = rotate(offset, up, yaw);
    // Pitch, limited so the eye never passes over the pole (where `up` and the
    // view direction would become parallel and the camera undefined).
    const double min_angle = std::numbers::pi / 180.0;
    const double angle_from_up = std::acos(std::clamp(dot(offset, up) / distance, -1.0, 1.0));
    const double new_angle = std::clamp(angle_from_up - pitch, min_angle, std::numbers::pi - min_angle);
    const Vec3d right = cross(offset, up);
    if (dot(right, right) > 0) offset = rotate(offset, normalize(right), angle_from_up - new_angle);
    camera.eye = camera.target + offset;
}

void pan(CameraParams& camera, double dx, double dy) {
    const Vec3d forward = normalize(camera.target - camera.eye);
    const Vec3d right = normalize(cross(forward, camera.up));
    const Vec3d true_up = cross(right, forward);
    const double view_height = 2.0 * length(camera.target - camera.eye) * std::tan(camera.fov_deg * std::numbers::pi / 360.0);
    // Moving the camera left makes the scene move right.
    const Vec3d shift = right * (-dx * view_height) + true_up * (-dy * view_height);
    camera.eye = camera.eye + shift;
    camera.target = camera.target + shift;
}

void dolly(CameraParams& camera, double factor) {
    const Vec3d offset = camera.eye - camera.target;
    const double distance = length(offset);
    const double new_distance = std::max(distance * factor, 1e-6);
    if (distance > 0) camera.eye = camera.target + offset * (new_distance / distance);
}

void frame_bounds(CameraParams& camera, const Aabb& bounds, double aspect) {
    if (bounds.empty()) return;
    const Vec3d lo = to_double(bounds.lo), hi = to_double(bounds.hi);
    const Vec3d centre = (lo + hi) * 0.5;
    double radius = 0.5 * length(hi - lo);
    if (radius == 0) radius = 0.5;
    const double half_v = camera.fov_deg * std::numbers::pi / 360.0;
    const double half_h = std::atan(std::tan(half_v) * std::max(aspect, 1e-3));
    const double distance = 1.05 * radius / std::sin(std::min(half_v, half_h));
    Vec3d direction = camera.eye - camera.target;
    if (dot(direction, direction) == 0) direction = {0, 0, 1};
    camera.target = centre;
    camera.eye = centre + normalize(direction) * distance;
}

std::string camera_cli_flags(const CameraParams& c) {
    char text[512];
    std::snprintf(text, sizeof text, "--eye %.9g,%.9g,%.9g --target %.9g,%.9g,%.9g --up %.9g,%.9g,%.9g --fov %.9g",
                  c.eye.x, c.eye.y, c.eye.z, c.target.x, c.target.y, c.target.z, c.up.x, c.up.y, c.up.z, c.fov_deg);
    return text;
}

}  // namespace accelviz
