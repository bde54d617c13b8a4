#include "core/render/camera.h"

#include <cmath>
#include <cstdlib>
#include <numbers>
#include <sstream>

namespace accelviz {

CameraParams default_camera(const Aabb& bounds) {
    CameraParams p;
    if (bounds.empty()) return p;
    const Vec3d lo = to_double(bounds.lo), hi = to_double(bounds.hi);
    const Vec3d c = (lo + hi) * 0.5;
    const Vec3d diag = hi - lo;
    double d = std::sqrt(dot(diag, diag));
    if (d == 0) d = 1;  // a single point: look at it from one unit away
    p.eye = c + normalize(Vec3d{0.4, 0.3, 1.0}) * (1.1 * d);
    p.target = c;
    p.up = {0, 1, 0};
    p.fov_deg = 45.0;
    return p;
}

Expected<Vec3d> parse_vec3(const std::string& text) {
    double v[3];
    const char* s = text.c_str();
    for (int i = 0; i < 3; ++i) {
        char* end = nullptr;
        v[i] = std::strtod(s, &end);
        if (end == s || !std::isfinite(v[i]))
            return Error{"expected three numbers x,y,z, got '" + text + "'"};
        s = end;
        if (i < 2) {
            if (*s != ',') return Error{"expected three numbers x,y,z, got '" + text + "'"};
            ++s;
        }
    }
    if (*s != '\0') return Error{"expected three numbers x,y,z, got '" + text + "'"};
    return Vec3d{v[0], v[1], v[2]};
}

std::optional<Error> validate(const CameraParams& p) {
    const Vec3d f = p.target - p.eye;
    if (dot(f, f) == 0) return Error{"camera: eye and target are the same point"};
    const Vec3d r = cross(f, p.up);
    if (dot(r, r) == 0) return Error{"camera: up is parallel to the view direction (or zero)"};
    if (!(p.fov_deg > 0 && p.fov_deg < 180)) return Error{"camera: --fov must be between 0 and 180 degrees"};
    return std::nullopt;
}

Camera::Camera(const CameraParams& params, int width, int height)
    : params_(params), width_(width), height_(height) {
    forward_ = normalize(params.target - params.eye);
    right_ = normalize(cross(forward_, params.up));
    true_up_ = cross(right_, forward_);
    tan_half_ = std::tan(params.fov_deg * std::numbers::pi / 360.0);
    aspect_ = double(width) / double(height);
}

Vec3d Camera::plane_direction(double px, double py) const {
    const double sx = (2.0 * px / width_ - 1.0) * tan_half_ * aspect_;
    const double sy = (1.0 - 2.0 * py / height_) * tan_half_;
    return forward_ + right_ * sx + true_up_ * sy;
}

Camera::ImagePoint Camera::project(Vec3d point) const {
    const Vec3d d = point - params_.eye;
    ImagePoint out;
    out.depth = dot(d, forward_);
    if (!(out.depth > 0)) return out;
    const double sx = dot(d, right_) / out.depth, sy = dot(d, true_up_) / out.depth;
    out.x = (sx / (tan_half_ * aspect_) + 1.0) * 0.5 * width_;
    out.y = (1.0 - sy / tan_half_) * 0.5 * height_;
    return out;
}

Ray Camera::ray(int x, int y) const {
    const Vec3d d = normalize(plane_direction(x + 0.5, y + 0.5));
    return Ray{to_float(params_.eye), to_float(d), 0.0f, kInfinity};
}

}  // namespace accelviz
