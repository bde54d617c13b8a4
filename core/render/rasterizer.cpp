// The CPU z-buffer rasterizer: the lecture's loop (基本光栅化算法), stage by stage.
//
//   initialize z_closest[] to ∞
//   for each triangle t in scene:                 // loop 1: triangles
//       t_proj = project_triangle(t)              //   stages 1-3 below
//       for each 2D sample s in t_proj's box:     // loop 2: pixel centres (stage 4)
//           if t_proj covers s:                   //   edge functions, top-left rule
//               if depth of t at s < z_closest[s] //   perspective-correct depth (stage 5)
//                   update z_closest[s], tri[s]
//   colour every pixel from the triangle it kept  // stage 6 (deferred shading)
//
// Everything is measured so that it lands exactly where the ray caster looks:
// the projection is the camera contract (core/render/camera.h) run backwards,
// and the depth kept per pixel is the distance t along that pixel's camera ray.

#include "core/render/rasterizer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/render/shading.h"

namespace accelviz {
namespace {

// ---------------------------------------------------------------------------
// Stage 1 — the view transform: world space to camera space.
// ---------------------------------------------------------------------------

/// A point in camera space: the eye is the origin, x runs along Camera::right,
/// y along Camera::true_up and z along Camera::forward. z is the depth.
struct CameraPoint {
    double x, y, z;
};

CameraPoint to_camera_space(Vec3 p, const Camera& camera) {
    const Vec3d d = to_double(p) - camera.params().eye;
    return {dot(d, camera.right()), dot(d, camera.true_up()), dot(d, camera.forward())};
}

bool is_finite(const CameraPoint& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

/// The near plane (see rasterizer.h): a fixed fraction of the farthest vertex's
/// distance, so it scales with the scene and the view. Always > 0, so points in
/// the eye plane (z = 0) are always clipped away.
double choose_near_plane(const std::vector<CameraPoint>& points) {
    double farthest = 0;
    for (const CameraPoint& p : points)
        if (is_finite(p)) farthest = std::max(farthest, std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z));
    // Every vertex at the eye: nothing can be seen; any positive plane will do.
    return farthest > 0 ? kNearPlaneRatio * farthest : 1.0;
}

// ---------------------------------------------------------------------------
// Stage 2 — clipping against the near plane z = z_near.
// A vertex behind the eye (z <= 0) has no sensible projection (x/z flips sign
// or divides by zero), so the part of the triangle in front of the plane is cut
// out first. This is one step of Sutherland–Hodgman polygon clipping: walk the
// edges, keep the vertices in front, and add a new vertex where an edge crosses.
// A triangle with 0, 1 or 2 vertices in front becomes nothing, a triangle, or a
// quadrilateral (two triangles).
// ---------------------------------------------------------------------------

struct ClippedPolygon {
    std::array<CameraPoint, 4> vertices;
    int count = 0;  ///< 0, 3 or 4
};

/// Where the segment from `in` (z >= z_near) to `out` (z < z_near) crosses the
/// plane. Always computed from the vertex in front, so the two triangles that
/// share a crossing edge compute the very same new vertex.
CameraPoint cut_at_near_plane(const CameraPoint& in, const CameraPoint& out, double z_near) {
    const double s = (z_near - in.z) / (out.z - in.z);  // in (0, 1]; out.z < in.z
    return {in.x + (out.x - in.x) * s, in.y + (out.y - in.y) * s, z_near};
}

ClippedPolygon clip_near(const std::array<CameraPoint, 3>& tri, double z_near) {
    ClippedPolygon poly;
    for (int i = 0; i < 3; ++i) {
        const CameraPoint& cur = tri[i];
        const CameraPoint& next = tri[(i + 1) % 3];
        const bool cur_in = cur.z >= z_near, next_in = next.z >= z_near;
        if (cur_in) poly.vertices[poly.count++] = cur;
        if (cur_in != next_in)
            poly.vertices[poly.count++] = cur_in ? cut_at_near_plane(cur, next, z_near)
                                                 : cut_at_near_plane(next, cur, z_near);
    }
    return poly;
}

// ---------------------------------------------------------------------------
// Stage 3 — projection to pixel coordinates.
// A camera-space point (x, y, z) lies on the ray whose image-plane coordinates
// are sx = x/z, sy = y/z. Solving the camera contract
//     sx = (2 px/W - 1) tan(fov/2) (W/H),   sy = (1 - 2 py/H) tan(fov/2)
// for (px, py) gives its pixel coordinates: x to the right, y DOWN, and the
// centre of pixel (i, j) at (i + 0.5, j + 0.5) — exactly where Camera::ray(i, j)
// points. Because every point has z >= z_near = kNearPlaneRatio * (distance of
// the farthest vertex) and |x|, |y| are at most that distance, |sx|, |sy| stay
// below 1 / kNearPlaneRatio: projected coordinates are always finite.
// ---------------------------------------------------------------------------

/// A projected vertex: pixel coordinates and the camera-space depth it came from.
struct ScreenVertex {
    double x, y;
    double z;
};

struct Projection {
    double half_width, half_height;
    double tan_x, tan_y;  ///< sx and sy of the image's right and top edges

    explicit Projection(const Camera& camera)
        : half_width(0.5 * camera.width()), half_height(0.5 * camera.height()),
          tan_x(camera.tan_half_fov() * (double(camera.width()) / camera.height())),
          tan_y(camera.tan_half_fov()) {}

    ScreenVertex operator()(const CameraPoint& p) const {
        const double sx = p.x / p.z, sy = p.y / p.z;
        return {(sx / tan_x + 1.0) * half_width, (1.0 - sy / tan_y) * half_height, p.z};
    }
};

// ---------------------------------------------------------------------------
// Stage 4 — coverage: edge functions at pixel centres (Pineda 1988).
// For an edge from a to b, E(p) = (b - a) × (p - a) is zero on the edge's line,
// positive on one side and negative on the other; a pixel centre is inside the
// triangle when all three edge functions are >= 0 (after orienting each so that
// the third vertex is on its positive side).
//
// Two details make neighbouring triangles fit together exactly:
//  - Both triangles sharing an edge must get exactly opposite values, bit for
//    bit, or rounding could leave a gap or draw a pixel twice. So each edge is
//    measured from the same endpoint in both (the one with the smaller x, then
//    y); then the rounding is identical and only the sign differs. (A centre
//    lying exactly on a vertex also gives exactly 0 on both edges through it.)
//  - A centre exactly on a shared edge (E = 0 for both) must go to one of them:
//    the top-left fill rule, as GPUs use. It goes to the triangle for which the
//    edge is a "left" edge (the inside is to its right) or a "top" edge (exactly
//    horizontal, the inside below it). For the other triangle the same edge is a
//    right or bottom edge, so exactly one of the two draws the pixel.
// ---------------------------------------------------------------------------

struct EdgeFunction {
    double origin_x, origin_y;  ///< the endpoint the function is measured from
    double dx, dy;              ///< other endpoint - origin, negated if needed so inside is E > 0
    bool owns_boundary;         ///< top-left rule: a centre with E == 0 counts as inside

    /// E(px, py) = dx (py - origin_y) - dy (px - origin_x), in two steps so that
    /// the first can be computed once per row. The steps are the same for every
    /// triangle, which keeps the shared-edge values bit-for-bit opposite.
    double row_term(double py) const { return dx * (py - origin_y); }
    double at(double row, double px) const { return row - dy * (px - origin_x); }
    bool covers(double e) const { return e > 0 || (e == 0 && owns_boundary); }
};

/// Sets up the edge from a to b of a triangle whose third vertex is `opposite`.
/// Returns false if `opposite` is on the edge's line: the triangle has no area
/// on screen (or a coordinate is not a number), and it produces no fragments.
bool make_edge(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& opposite, EdgeFunction& edge) {
    const bool a_first = a.x < b.x || (a.x == b.x && a.y < b.y);
    const ScreenVertex& from = a_first ? a : b;
    const ScreenVertex& to = a_first ? b : a;
    edge = {from.x, from.y, to.x - from.x, to.y - from.y, false};
    const double e_opposite = edge.at(edge.row_term(opposite.y), opposite.x);
    if (!std::isfinite(e_opposite) || e_opposite == 0) return false;
    if (e_opposite < 0) {  // flip so that the inside (the third vertex's side) is positive
        edge.dx = -edge.dx;
        edge.dy = -edge.dy;
    }
    // E's gradient (which points inside) is (-dy, dx), with y pointing down the image.
    //  left edge: the inside is to the right (-dy > 0);
    //  top edge:  horizontal (dy == 0), the inside below (dx > 0).
    edge.owns_boundary = edge.dy < 0 || (edge.dy == 0 && edge.dx > 0);
    return true;
}

/// The first pixel index whose centre (i + 0.5) is >= lo, clamped to [0, n]; and
/// one past the last whose centre is <= hi. Clamping happens in double, before
/// converting, so huge coordinates cannot overflow an int.
int first_centre_at_or_after(double lo, int n) {
    const double i = std::ceil(lo - 0.5);
    return i <= 0 ? 0 : (i >= n ? n : int(i));
}
int past_last_centre_at_or_before(double hi, int n) {
    const double i = std::floor(hi - 0.5) + 1.0;
    return i <= 0 ? 0 : (i >= n ? n : int(i));
}

/// Where the per-triangle stages write: the frame (z-buffer and triangle ids),
/// the length of each pixel's unnormalised ray direction, and the statistics.
struct RasterTarget {
    Frame& frame;
    const std::vector<double>& ray_length;  ///< |Camera::plane_direction| at each pixel centre
    RasterStats& stats;
    RasterHistory* history = nullptr;       ///< the writes, when recorded
    uint64_t overwrites = 0;                ///< writes over an earlier triangle's
};

/// Stages 4 and 5 for one projected (and clipped) triangle.
void rasterize_triangle(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2, uint32_t id,
                        RasterTarget& target) {
    // Edge k is opposite vertex k, so its function, divided by the sum of all
    // three, is vertex k's barycentric weight.
    EdgeFunction e0, e1, e2;
    if (!make_edge(v1, v2, v0, e0) || !make_edge(v2, v0, v1, e1) || !make_edge(v0, v1, v2, e2)) return;

    // The screen bounding box, clipped to the image (the lecture: 光栅化：将测试点
    // 限制在三角形的包围盒内 — only test the samples inside the triangle's box).
    Frame& frame = target.frame;
    const int x_begin = first_centre_at_or_after(std::min({v0.x, v1.x, v2.x}), frame.width);
    const int x_end = past_last_centre_at_or_before(std::max({v0.x, v1.x, v2.x}), frame.width);
    const int y_begin = first_centre_at_or_after(std::min({v0.y, v1.y, v2.y}), frame.height);
    const int y_end = past_last_centre_at_or_before(std::max({v0.y, v1.y, v2.y}), frame.height);
    if (x_begin >= x_end || y_begin >= y_end) return;
    target.stats.pixels_tested += uint64_t(x_end - x_begin) * uint64_t(y_end - y_begin);

    // Stage 5 — perspective-correct depth. Depth z itself is NOT linear across
    // the screen (far parts of a triangle are squeezed together), but 1/z is:
    // a plane a x + b y + c z = d seen through the pinhole satisfies
    // 1/z = (a sx + b sy + c) / d, affine in the screen position. So interpolate
    // 1/z with the screen-space barycentrics and invert.
    const double inv_z0 = 1.0 / v0.z, inv_z1 = 1.0 / v1.z, inv_z2 = 1.0 / v2.z;

    for (int y = y_begin; y < y_end; ++y) {
        const double py = y + 0.5;
        const double row0 = e0.row_term(py), row1 = e1.row_term(py), row2 = e2.row_term(py);
        for (int x = x_begin; x < x_end; ++x) {
            const double px = x + 0.5;
            const double w0 = e0.at(row0, px), w1 = e1.at(row1, px), w2 = e2.at(row2, px);
            if (!(e0.covers(w0) && e1.covers(w1) && e2.covers(w2))) continue;

            // A fragment: this triangle covers this pixel centre.
            const size_t i = frame.index(x, y);
            ++frame.tests[i];
            ++target.stats.fragments;

            // Barycentrics are w_k / (w0 + w1 + w2); all w_k >= 0 here and at most
            // two are 0, so 1/z is a positive blend of the vertices' 1/z.
            const double inv_z = (w0 * inv_z0 + w1 * inv_z1 + w2 * inv_z2) / (w0 + w1 + w2);
            // Camera-space depth z to ray distance t: the pixel's ray direction
            // forward + sx right + sy true_up has forward component 1, so the
            // point at depth z is at distance z |direction| along the ray.
            const auto t = float(target.ray_length[i] / inv_z);

            // The z-test, with the ray caster's order (is_closer): smaller t, and
            // on an exact tie the smaller triangle id.
            if (is_closer(t, id, Hit{frame.tri[i], frame.depth[i]})) {
                if (frame.tri[i] != Hit::kNoHit && frame.tri[i] != id) ++target.overwrites;
                frame.depth[i] = t;
                frame.tri[i] = id;
                ++target.stats.depth_writes;
                if (target.history) {
                    target.history->write_pixel.push_back(uint32_t(i));
                    target.history->write_tri.push_back(id);
                }
            }
        }
    }
}

}  // namespace

Frame rasterize(const Mesh& mesh, const Camera& camera, RasterStats* stats_out, RasterHistory* history) {
    const int width = std::max(camera.width(), 0), height = std::max(camera.height(), 0);
    Frame frame(width, height);  // depth = +inf, tri = none: "initialize z_closest[] to ∞"
    frame.tests.assign(frame.depth.size(), 0);
    RasterStats stats;
    stats.triangles_in = mesh.triangle_count();

    // Stage 1: every vertex to camera space, once (vertices are shared by triangles).
    std::vector<CameraPoint> points(mesh.positions.size());
    for (size_t v = 0; v < points.size(); ++v) points[v] = to_camera_space(mesh.positions[v], camera);
    stats.z_near = choose_near_plane(points);

    // The length of each pixel's ray direction before normalisation, for stage 5.
    std::vector<double> ray_length(frame.depth.size());
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const Vec3d d = camera.plane_direction(x + 0.5, y + 0.5);
            ray_length[frame.index(x, y)] = std::sqrt(dot(d, d));
        }

    RasterTarget target{frame, ray_length, stats, history};
    if (history) {
        *history = RasterHistory{};
        for (auto* counts : {&history->writes_before, &history->fragments_before, &history->overwrites_before})
            counts->reserve(mesh.triangle_count() + 1);
    }
    auto note_counts = [&] {
        if (!history) return;
        history->writes_before.push_back(stats.depth_writes);
        history->fragments_before.push_back(stats.fragments);
        history->overwrites_before.push_back(target.overwrites);
    };
    const Projection project(camera);
    for (uint32_t id = 0; id < mesh.triangle_count(); ++id) {
        note_counts();
        const std::array<CameraPoint, 3> tri = {points[mesh.indices[id][0]], points[mesh.indices[id][1]],
                                                points[mesh.indices[id][2]]};
        if (!is_finite(tri[0]) || !is_finite(tri[1]) || !is_finite(tri[2])) continue;  // NaN or inf input

        // Stage 2: clip; stage 3: project; stages 4-5: walk the pixels. A
        // quadrilateral left by clipping is split into two triangles (a fan).
        const ClippedPolygon poly = clip_near(tri, stats.z_near);
        std::array<ScreenVertex, 4> screen;
        for (int k = 0; k < poly.count; ++k) screen[k] = project(poly.vertices[k]);
        for (int k = 1; k + 1 < poly.count; ++k) {
            ++stats.triangles_rasterized;
            rasterize_triangle(screen[0], screen[k], screen[k + 1], id, target);
        }
    }

    note_counts();  // the totals after the last triangle

    // Stage 6 — shading, deferred: the colour depends only on the triangle kept
    // and the pixel's ray, so shading once per pixel after the z-test gives the
    // same picture as shading every fragment, for less work. The direction is the
    // ray caster's own (float) ray, so both renderers give identical colours
    // wherever they see the same triangle.
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const size_t i = frame.index(x, y);
            frame.colour.pixels[i] =
                frame.tri[i] != Hit::kNoHit ? headlight_shade(mesh.triangle(frame.tri[i]), camera.ray(x, y).dir)
                                            : kBackground;
        }

    if (stats_out) *stats_out = stats;
    return frame;
}

}  // namespace accelviz
