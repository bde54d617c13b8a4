#pragma once
/// The camera contract (exact; other tools reproduce it):
///   forward = normalize(target - eye); right = normalize(cross(forward, up));
///   true_up = cross(right, forward);
///   pixel (x, y), y = 0 the top row:
///     sx = (2(x+0.5)/W - 1) * tan(fov/2) * (W/H),  sy = (1 - 2(y+0.5)/H) * tan(fov/2)
///   ray origin = eye, direction = normalize(forward + sx right + sy true_up), t in [0, inf).
///   fov is the vertical field of view in degrees.
/// The set-up is computed in double precision and each ray rounded once to float.

#include <optional>
#include <string>

#include "core/math/aabb.h"
#include "core/util/expected.h"

namespace accelviz {

struct CameraParams {
    Vec3d eye{0, 0, 1};
    Vec3d target{0, 0, 0};
    Vec3d up{0, 1, 0};
    double fov_deg = 45.0;
    bool operator==(const CameraParams&) const = default;
};

/// The default view of a scene with bounds lo, hi: c = (lo+hi)/2, d = |hi-lo|,
/// eye = c + normalize(0.4, 0.3, 1.0) * 1.1 * d, target = c, up = +y, fov 45.
/// An empty scene gets the unit view from (0,0,1) to the origin.
CameraParams default_camera(const Aabb& scene_bounds);

/// Parses "x,y,z" (three finite numbers).
Expected<Vec3d> parse_vec3(const std::string& text);

/// Checks that the parameters define a camera (eye != target, up not parallel
/// to the view direction, 0 < fov < 180).
std::optional<Error> validate(const CameraParams& params);

class Camera {
public:
    Camera(const CameraParams& params, int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }
    const CameraParams& params() const { return params_; }
    Vec3d forward() const { return forward_; }
    Vec3d right() const { return right_; }
    Vec3d true_up() const { return true_up_; }
    /// tan(fov/2): sy of the top edge of the image.
    double tan_half_fov() const { return tan_half_; }

    /// The unnormalised direction forward + sx right + sy true_up of a point on the
    /// image plane at distance 1; (px, py) in pixels, (x+0.5, y+0.5) being a centre.
    Vec3d plane_direction(double px, double py) const;
    /// The primary ray through the centre of pixel (x, y).
    Ray ray(int x, int y) const;

    /// Where a point appears in the image: the inverse of plane_direction, in pixels
    /// (x right, y down; the pixel (x, y) covers [x, x+1) x [y, y+1)), and its depth
    /// along forward. Only meaningful when depth > 0 (the point is before the eye).
    struct ImagePoint {
        double x = 0, y = 0, depth = 0;
    };
    ImagePoint project(Vec3d point) const;

private:
    CameraParams params_;
    int width_, height_;
    Vec3d forward_, right_, true_up_;
    double tan_half_, aspect_;
};

}  // namespace accelviz
