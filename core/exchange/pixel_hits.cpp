#include "core/exchange/pixel_hits.h"

#include <array>
#include <charconv>
#include <optional>
#include <cmath>
#include <sstream>

namespace accelviz {

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

template <class T>
bool parse_number(std::string_view s, T& out) {
    s = trim(s);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

/// Where the ray meets triangle `tri`'s plane inside the triangle (barycentrics within
/// 1e-6 of it), in double; nothing if it does not.
std::optional<double> ray_meets(const Mesh& mesh, uint32_t tri, const Ray& ray) {
    auto d = [](Vec3 v) { return std::array<double, 3>{v.x, v.y, v.z}; };
    const auto p0 = d(mesh.vertex(tri, 0)), p1 = d(mesh.vertex(tri, 1)), p2 = d(mesh.vertex(tri, 2));
    const auto o = d(ray.origin), dir = d(ray.dir);
    auto sub = [](const auto& a, const auto& b) { return std::array<double, 3>{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
    auto cross = [](const auto& a, const auto& b) {
        return std::array<double, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    };
    auto dot = [](const auto& a, const auto& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    const auto e1 = sub(p1, p0), e2 = sub(p2, p0), p = cross(dir, e2);
    const double det = dot(e1, p);
    if (det == 0.0) return std::nullopt;
    const auto s = sub(o, p0), q = cross(s, e1);
    const double u = dot(s, p) / det, v = dot(dir, q) / det;
    constexpr double kSlack = 1e-6;
    if (u < -kSlack || v < -kSlack || u + v > 1.0 + kSlack) return std::nullopt;
    return dot(e2, q) / det;
}

}  // namespace

Expected<std::vector<PixelHit>> parse_pixel_hits(const std::string& text, int width, int height) {
    std::vector<PixelHit> out;
    std::istringstream in(text);
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        const std::string_view l = trim(line);
        if (l.empty()) continue;
        std::vector<std::string_view> fields;
        size_t start = 0;
        for (size_t comma; (comma = l.find(',', start)) != std::string_view::npos; start = comma + 1)
            fields.push_back(l.substr(start, comma - start));
        fields.push_back(l.substr(start));
        const std::string where = "line " + std::to_string(number) + ": ";
        PixelHit h;
        long long tri = 0;
        if (fields.size() != 4) return Error{where + "expected x,y,triangle,t (4 fields), found " + std::to_string(fields.size())};
        if (!parse_number(fields[0], h.x) || !parse_number(fields[1], h.y)) {
            if (out.empty() && number == 1) continue;  // a header
            return Error{where + "x and y must be whole numbers"};
        }
        if (h.x < 0 || h.y < 0 || h.x >= width || h.y >= height)
            return Error{where + "pixel (" + std::to_string(h.x) + ", " + std::to_string(h.y) + ") is outside the " +
                         std::to_string(width) + " x " + std::to_string(height) + " image (--width, --height)"};
        if (!parse_number(fields[2], tri) || tri < -1 || tri > 0xFFFFFFFELL)
            return Error{where + "the triangle must be an id, or -1 for a miss"};
        h.tri = tri < 0 ? Hit::kNoHit : uint32_t(tri);
        if (h.tri != Hit::kNoHit) {
            double t = 0;
            if (!parse_number(fields[3], t) || !std::isfinite(t)) return Error{where + "t must be a finite number"};
            h.t = float(t);
        }
        out.push_back(h);
    }
    return out;
}

PixelHitComparison compare_pixel_hits(const std::vector<PixelHit>& hits, const Camera& camera, const Mesh& mesh,
                                      const Accelerator& reference) {
    PixelHitComparison out;
    auto close = [](double a, double b) { return std::abs(a - b) <= kPixelHitRelativeT * std::abs(b); };
    for (const PixelHit& h : hits) {
        ++out.pixels;
        const Ray ray = camera.ray(h.x, h.y);
        const Hit right = reference.intersect_closest(ray);
        const bool same_t = right.found() && h.tri != Hit::kNoHit && close(h.t, right.t);
        std::optional<double> tie;
        if (same_t && h.tri != right.tri && h.tri < mesh.triangle_count()) tie = ray_meets(mesh, h.tri, ray);
        if (h.tri == right.tri && (!right.found() || same_t)) {
            ++out.agree;
        } else if (tie && close(*tie, right.t)) {
            ++out.agree;
            ++out.ties;
        } else {
            out.differ.push_back({h, right});
        }
    }
    return out;
}

}  // namespace accelviz
