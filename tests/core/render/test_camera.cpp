// The camera contract, checked against its formulas written out independently.
#include <gtest/gtest.h>

#include <cmath>

#include "core/render/camera.h"

using namespace accelviz;

TEST(CameraContract, CentrePixelLooksForwardForOddSizes) {
    const Camera cam({{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 60}, 3, 3);
    const Ray r = cam.ray(1, 1);
    EXPECT_FLOAT_EQ(r.dir.x, 0);
    EXPECT_FLOAT_EQ(r.dir.y, 0);
    EXPECT_FLOAT_EQ(r.dir.z, -1);
    EXPECT_EQ(r.origin, Vec3(0, 0, 5));
    EXPECT_EQ(r.t_min, 0.0f);
    EXPECT_TRUE(std::isinf(r.t_max));
}

TEST(CameraContract, TopRowIsYZeroAndRightIsPositiveX) {
    const Camera cam({{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 90}, 4, 2);
    EXPECT_GT(cam.ray(0, 0).dir.y, 0);   // top row looks up
    EXPECT_LT(cam.ray(0, 1).dir.y, 0);   // bottom row looks down
    EXPECT_LT(cam.ray(0, 0).dir.x, 0);   // left column looks left
    EXPECT_GT(cam.ray(3, 0).dir.x, 0);
}

TEST(CameraContract, MatchesTheFormulasExactly) {
    const CameraParams p{{1, 2, 3}, {-2, 0.5, 1}, {0, 1, 0.2}, 37};
    const int W = 64, H = 48;
    const Camera cam(p, W, H);
    auto norm = [](double x, double y, double z) { double l = std::sqrt(x * x + y * y + z * z); return std::array<double, 3>{x / l, y / l, z / l}; };
    const auto f = norm(-3, -1.5, -2);
    // right = normalize(cross(forward, up))
    const auto r = norm(f[1] * 0.2 - f[2] * 1, f[2] * 0 - f[0] * 0.2, f[0] * 1 - f[1] * 0);
    const std::array<double, 3> u{r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]};
    const double th = std::tan(37.0 * M_PI / 360.0);
    for (int y : {0, 17, 47})
        for (int x : {0, 31, 63}) {
            const double sx = (2 * (x + 0.5) / W - 1) * th * (double(W) / H);
            const double sy = (1 - 2 * (y + 0.5) / H) * th;
            const auto d = norm(f[0] + sx * r[0] + sy * u[0], f[1] + sx * r[1] + sy * u[1], f[2] + sx * r[2] + sy * u[2]);
            const Ray ray = cam.ray(x, y);
            EXPECT_EQ(ray.dir.x, float(d[0]));
            EXPECT_EQ(ray.dir.y, float(d[1]));
            EXPECT_EQ(ray.dir.z, float(d[2]));
        }
}

TEST(CameraContract, ProjectIsTheInverseOfThePixelRays) {
    const CameraParams p{{1, 2, 3}, {-2, 0.5, 1}, {0, 1, 0.2}, 37};
    const Camera cam(p, 64, 48);
    for (int y : {0, 17, 47})
        for (int x : {0, 31, 63})
            for (double distance : {0.5, 3.0, 40.0}) {
                const Vec3d d = normalize(cam.plane_direction(x + 0.5, y + 0.5));
                const Camera::ImagePoint q = cam.project(p.eye + d * distance);
                EXPECT_NEAR(q.x, x + 0.5, 1e-9);
                EXPECT_NEAR(q.y, y + 0.5, 1e-9);
                EXPECT_NEAR(q.depth, distance * dot(d, cam.forward()), 1e-9);
            }
    EXPECT_LT(cam.project(p.eye - cam.forward()).depth, 0);  // behind the eye
}

TEST(CameraContract, DefaultViewFramesTheBounds) {
    const Aabb box{{-1, -2, -3}, {1, 2, 3}};
    const CameraParams p = default_camera(box);
    const double d = std::sqrt(4.0 + 16.0 + 36.0);
    const double n = std::sqrt(0.16 + 0.09 + 1.0);
    EXPECT_NEAR(p.eye.x, 0.4 / n * 1.1 * d, 1e-12);
    EXPECT_NEAR(p.eye.y, 0.3 / n * 1.1 * d, 1e-12);
    EXPECT_NEAR(p.eye.z, 1.0 / n * 1.1 * d, 1e-12);
    EXPECT_EQ(p.target.x, 0);
    EXPECT_EQ(p.up.y, 1);
    EXPECT_EQ(p.fov_deg, 45);
}

TEST(CameraContract, InvalidCamerasAreRejected) {
    EXPECT_TRUE(validate({{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, 45}).has_value());
    EXPECT_TRUE(validate({{0, 0, 1}, {0, 0, 0}, {0, 0, 1}, 45}).has_value());
    EXPECT_TRUE(validate({{0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 180}).has_value());
    EXPECT_FALSE(validate({{0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 45}).has_value());
}

TEST(CameraContract, ParseVec3) {
    auto v = parse_vec3("1,-2.5,3e2");
    ASSERT_TRUE(v.ok());
    EXPECT_EQ(v->x, 1);
    EXPECT_EQ(v->y, -2.5);
    EXPECT_EQ(v->z, 300);
    EXPECT_FALSE(parse_vec3("1,2").ok());
    EXPECT_FALSE(parse_vec3("1,2,3,4").ok());
    EXPECT_FALSE(parse_vec3("a,b,c").ok());
    EXPECT_FALSE(parse_vec3("1,nan,3").ok());
}
