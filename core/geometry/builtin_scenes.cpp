// Built-in scenes: the lecture's test cases made on the spot, "builtin:NAME?k=v&k=v".
//
// Every scene but `instances` (which repeats a mesh loaded from a file) is a pure
// function of its parameters. Seeded scenes draw from Rng
// (core/util/random.h); nothing here calls libm's sin/cos/pow, whose last bits
// may differ between machines: only + - * / and sqrt, which IEEE 754 rounds
// exactly, and -ffp-contract=off keeps the compiler from fusing them.
//
// [SECTION] Parameters      parsing "k=v&k=v" against a table of accepted keys
// [SECTION] Shapes          cube, Cornell box, teapot, icosphere, stadium
// [SECTION] Tricky cases    same centroid, same box, soup
// [SECTION] Big scenes      a mesh repeated on a grid (instances)
// [SECTION] Registry        the table make_builtin and builtin_scenes read
#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "core/geometry/scene.h"
#include "core/util/random.h"

namespace accelviz {

namespace {

// ---------------------------------------------------------------------------
// [SECTION] Parameters
// ---------------------------------------------------------------------------

enum class ParamKind {
    Count,  ///< a whole number in [min_value, max_value]
    Real,   ///< a finite number in [min_value, max_value]
    Seed,   ///< any 64-bit unsigned integer (min_value/max_value unused)
    Source, ///< an OBJ path or built-in scene, up to the next '&' (default kDefaultSource)
};

/// The default of a Source parameter.
constexpr const char* kDefaultSource = "builtin:teapot";

/// One parameter a built-in accepts.
struct ParamSpec {
    const char* name;
    ParamKind kind;
    double min_value;
    double max_value;
    double default_value;
};

/// A parsed value: `whole` for Count and Seed, `real` for Real and Count.
struct ParamValue {
    uint64_t whole = 0;
    double real = 0;
    std::string text;  ///< Source
};

/// The values of all of a scene's parameters, defaults filled in.
struct Params {
    const std::vector<ParamSpec>* specs = nullptr;
    std::vector<ParamValue> values;  ///< parallel to *specs
    WorkProgress* progress = nullptr;  ///< a scene that loads another (instances) reports and may cancel here
    MeshCache cache = MeshCache::Skip;  ///< and reads the mesh cache so

    const ParamValue& get(std::string_view name) const {
        for (size_t i = 0; i < specs->size(); ++i)
            if (name == (*specs)[i].name) return values[i];
        static const ParamValue kNone{};  // immutable; only reached by a typo in this file
        return kNone;
    }
    uint64_t whole(std::string_view name) const { return get(name).whole; }
    double real(std::string_view name) const { return get(name).real; }
    const std::string& text(std::string_view name) const { return get(name).text; }
};

/// A number as a person writes it: whole numbers without ".0" or exponent.
std::string format_number(double x) {
    if (x == std::floor(x) && std::abs(x) < 1e15) return std::to_string(static_cast<long long>(x));
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
    return std::string(buffer, result.ptr);
}

/// "n (integer 1..64, default 8)".
std::string describe(const ParamSpec& p) {
    switch (p.kind) {
        case ParamKind::Count:
            return std::string(p.name) + " (integer " + format_number(p.min_value) + ".." + format_number(p.max_value) +
                   ", default " + format_number(p.default_value) + ")";
        case ParamKind::Real:
            return std::string(p.name) + " (number " + format_number(p.min_value) + ".." + format_number(p.max_value) +
                   ", default " + format_number(p.default_value) + ")";
        case ParamKind::Seed:
            return std::string(p.name) + " (integer 0..2^64-1, default " + format_number(p.default_value) + ")";
        case ParamKind::Source:
            return std::string(p.name) + " (an OBJ path or builtin:NAME without '&', default " + kDefaultSource + ")";
    }
    return p.name;
}

/// "n (integer 1..64, default 8), seed (...)" or "no parameters".
std::string describe(const std::vector<ParamSpec>& specs) {
    if (specs.empty()) return "no parameters";
    std::string out;
    for (const ParamSpec& p : specs) out += (out.empty() ? "" : ", ") + describe(p);
    return out;
}

/// A whole word as an unsigned integer: ok, not a number, or too large for 64 bits.
enum class WholeParse { Ok, NotInteger, TooLarge };
WholeParse parse_whole(std::string_view text, uint64_t& out) {
    if (text.empty()) return WholeParse::NotInteger;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    if (end != text.data() + text.size()) return WholeParse::NotInteger;
    if (ec == std::errc::result_out_of_range) return WholeParse::TooLarge;
    return ec == std::errc() ? WholeParse::Ok : WholeParse::NotInteger;
}

bool parse_real(std::string_view text, double& out) {
    if (text.empty()) return false;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    return ec == std::errc() && end == text.data() + text.size() && std::isfinite(out);
}

/// Parses "k=v&k=v" (may be empty) against `specs`. `fail(reason)` makes the error.
template <class Fail>
Expected<Params> parse_params(const std::vector<ParamSpec>& specs, std::string_view query, Fail&& fail) {
    Params params;
    params.specs = &specs;
    params.values.resize(specs.size());
    for (size_t i = 0; i < specs.size(); ++i) {
        params.values[i].whole = static_cast<uint64_t>(specs[i].default_value);
        params.values[i].real = specs[i].default_value;
        if (specs[i].kind == ParamKind::Source) params.values[i].text = kDefaultSource;
    }
    std::vector<bool> given(specs.size(), false);

    // "k=v&k=v"; an empty query (nothing after '?') is no parameters, but an empty
    // item ("n=1&", "&n=1", "n=1&&seed=2") is an error.
    for (bool more = !query.empty(); more;) {
        const size_t amp = query.find('&');
        const std::string_view item = query.substr(0, amp);
        more = amp != std::string_view::npos;
        if (more) query.remove_prefix(amp + 1);

        const size_t eq = item.find('=');
        const std::string_view key = item.substr(0, eq);
        if (key.empty()) return fail(item.empty() ? "empty parameter (a stray '&')" : "empty parameter name in '" + std::string(item) + "'");
        size_t index = 0;
        while (index < specs.size() && key != specs[index].name) ++index;
        if (index == specs.size()) return fail("unknown parameter '" + std::string(key) + "'");
        if (eq == std::string_view::npos)
            return fail("parameter '" + std::string(key) + "' has no value (write " + std::string(key) + "=VALUE)");
        if (given[index]) return fail("parameter '" + std::string(key) + "' given twice");
        given[index] = true;

        const ParamSpec& spec = specs[index];
        const std::string_view text = item.substr(eq + 1);
        const std::string shown = std::string(key) + "=" + std::string(text);
        ParamValue& value = params.values[index];
        if (spec.kind == ParamKind::Source) {
            if (text.empty()) return fail("parameter '" + std::string(key) + "' is empty");
            value.text = text;
        } else if (spec.kind == ParamKind::Real) {
            if (!parse_real(text, value.real)) return fail(shown + " is not a number");
            if (!(value.real >= spec.min_value && value.real <= spec.max_value)) return fail(shown + " is out of range");
        } else {
            const WholeParse parsed = parse_whole(text, value.whole);
            if (parsed == WholeParse::NotInteger) return fail(shown + " is not a non-negative integer");
            if (parsed == WholeParse::TooLarge) return fail(shown + " is out of range");
            value.real = static_cast<double>(value.whole);
            if (spec.kind == ParamKind::Count && !(value.real >= spec.min_value && value.real <= spec.max_value))
                return fail(shown + " is out of range");
        }
    }
    return params;
}

// ---------------------------------------------------------------------------
// [SECTION] Shapes
// ---------------------------------------------------------------------------

/// Appends the quad a b c d (in order around its edge) as triangles (a, b, c) and
/// (a, c, d), wound so that the normal (b - a) x (c - a) points along `toward`.
void add_quad(Mesh& mesh, Vec3 a, Vec3 b, Vec3 c, Vec3 d, Vec3 toward) {
    if (dot(cross(b - a, c - a), toward) < 0) std::swap(b, d);
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {a, b, c, d});
    mesh.indices.push_back({base, base + 1, base + 2});
    mesh.indices.push_back({base, base + 2, base + 3});
}

/// The cube [-1,1]^3: 8 shared vertices, 12 triangles, normals pointing out.
Mesh make_cube(const Params&) {
    Mesh mesh;
    // Vertex i: x from bit 0, y from bit 1, z from bit 2 (0 → -1, 1 → +1).
    for (uint32_t i = 0; i < 8; ++i)
        mesh.positions.push_back({(i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, (i & 4) ? 1.0f : -1.0f});
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, w = (axis + 2) % 3;  // e_u x e_w = e_axis
        for (uint32_t side = 0; side < 2; ++side) {
            auto corner = [&](uint32_t su, uint32_t sw) { return (side << axis) | (su << u) | (sw << w); };
            // (0,0) (1,0) (1,1) (0,1) runs counter-clockwise seen from +axis: right for the
            // +axis face, reversed for the -axis face.
            uint32_t q[4] = {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)};
            if (side == 0) std::swap(q[1], q[3]);
            mesh.indices.push_back({q[0], q[1], q[2]});
            mesh.indices.push_back({q[0], q[2], q[3]});
        }
    }
    return mesh;
}

/// The Cornell box: the published measurements of the real box (Cornell Program of
/// Computer Graphics, in millimetres), turned 180° about the vertical so that the
/// open side faces +z (towards the default camera) and the red wall is on the
/// left, and scaled to units of 10 cm: the room is 5.56 wide (x), 5.488 high (y)
/// and 5.592 deep (z), with the back wall at z = 0. The measured room is very
/// slightly skewed; this one is square. 32 triangles.
Mesh make_cornell(const Params&) {
    constexpr double kWidth = 556.0, kHeight = 548.8, kDepth = 559.2;
    // The published frame: camera at -z looking +z, red wall at x = 556.
    auto at = [&](double x, double y, double z) {
        return to_float(Vec3d{(kWidth - x) / 100.0, y / 100.0, (kDepth - z) / 100.0});
    };
    Mesh mesh;
    const Vec3 centre = at(kWidth / 2, kHeight / 2, kDepth / 2);
    auto room_quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d) {  // facing into the room
        add_quad(mesh, a, b, c, d, centre - (a + b + c + d) * 0.25f);
    };
    const double W = kWidth, H = kHeight, D = kDepth;
    room_quad(at(0, 0, 0), at(W, 0, 0), at(W, 0, D), at(0, 0, D));  // floor
    room_quad(at(0, H, 0), at(W, H, 0), at(W, H, D), at(0, H, D));  // ceiling
    room_quad(at(0, 0, D), at(W, 0, D), at(W, H, D), at(0, H, D));  // back wall
    room_quad(at(W, 0, 0), at(W, 0, D), at(W, H, D), at(W, H, 0));  // red wall (left)
    room_quad(at(0, 0, 0), at(0, 0, D), at(0, H, D), at(0, H, 0));  // green wall (right)

    // The light: 130 x 105 mm, 1 cm under the ceiling (the real one sits in a hole), facing down.
    const double light_y = H - 10.0;
    add_quad(mesh, at(343, light_y, 227), at(343, light_y, 332), at(213, light_y, 332), at(213, light_y, 227),
             {0, -1, 0});

    // A block standing on the floor: its top's four corners (x, z) at height h.
    auto block = [&](const double (&top)[4][2], double h) {
        Vec3 centre_top{0, 0, 0};
        for (const auto& c : top) centre_top += at(c[0], h, c[1]) * 0.25f;
        const Vec3 inside = centre_top - Vec3{0, float(h / 200.0), 0};
        add_quad(mesh, at(top[0][0], h, top[0][1]), at(top[1][0], h, top[1][1]), at(top[2][0], h, top[2][1]),
                 at(top[3][0], h, top[3][1]), {0, 1, 0});
        for (int k = 0; k < 4; ++k) {
            const auto& p = top[k];
            const auto& q = top[(k + 1) % 4];
            const Vec3 a = at(p[0], 0, p[1]), b = at(q[0], 0, q[1]), c = at(q[0], h, q[1]), d = at(p[0], h, p[1]);
            add_quad(mesh, a, b, c, d, (a + b + c + d) * 0.25f - inside);
        }
    };
    const double short_block[4][2] = {{130, 65}, {82, 225}, {240, 272}, {290, 114}};
    const double tall_block[4][2] = {{423, 247}, {265, 296}, {314, 456}, {472, 406}};
    block(short_block, 165.0);
    block(tall_block, 330.0);
    return mesh;
}

/// The Cornell box whose tall block is a mirror (its 10 triangles, the last ones):
/// what a reflection ray sees, the room and the short block from another side.
Mesh make_cornell_mirror(const Params& params) {
    Mesh mesh = make_cornell(params);
    constexpr size_t kTallBlockTriangles = 10;
    mesh.mirror.assign(mesh.triangle_count(), 0);
    std::fill(mesh.mirror.end() - kTallBlockTriangles, mesh.mirror.end(), uint8_t(1));
    return mesh;
}

}  // namespace

Vec3 bezier_patch_point(const BezierPatch& patch, double u, double v) {
    // Cubic Bernstein weights. At t = 0 they are exactly (1, 0, 0, 0) and at t = 1
    // exactly (0, 0, 0, 1), so a patch edge depends only on its own control points.
    auto bernstein = [](double t, double (&b)[4]) {
        const double s = 1.0 - t;
        b[0] = s * s * s;
        b[1] = 3.0 * t * s * s;
        b[2] = 3.0 * t * t * s;
        b[3] = t * t * t;
    };
    double bu[4], bv[4];
    bernstein(u, bu);
    bernstein(v, bv);
    Vec3d point{0, 0, 0};
    for (int i = 0; i < 4; ++i) {
        Vec3d row{0, 0, 0};  // the curve of control row i at v
        for (int j = 0; j < 4; ++j) row = row + to_double(patch.control[i][j]) * bv[j];
        point = point + row * bu[i];
    }
    return to_float(point);
}

namespace {

/// Appends Newell's teapot, each patch tessellated into n x n quads (two triangles
/// each), turned from z up to y up ((x, y, z) → (x, z, -y)) and moved so that it
/// stands on y = 0 with the body's axis on x = z = 0, then scaled by `scale`
/// (height 0.75 at scale 1).
///
/// Vertices with bit-identical positions are welded, so patches share their seams.
/// Each lid-knob patch collapses to one point along an edge; the triangles there
/// would have two identical corners and zero area. We drop them (our choice;
/// degenerate triangles are legal input everywhere): n per knob patch, so the
/// teapot has 28 * 2n^2 - 4n triangles.
void append_teapot(Mesh& mesh, int n, double scale) {
    struct Key {
        uint32_t x, y, z;
        bool operator==(const Key&) const = default;
    };
    struct KeyHash {
        size_t operator()(const Key& k) const {
            return size_t(k.x) * 0x9e3779b97f4a7c15ull ^ size_t(k.y) * 0xc2b2ae3d27d4eb4full ^ size_t(k.z);
        }
    };
    std::unordered_map<Key, uint32_t, KeyHash> welded;
    auto weld = [&](Vec3 p) {
        p = p + Vec3{0.0f, 0.0f, 0.0f};  // -0 + 0 = +0: one key for both zeros
        const Key key{std::bit_cast<uint32_t>(p.x), std::bit_cast<uint32_t>(p.y), std::bit_cast<uint32_t>(p.z)};
        const auto [it, inserted] = welded.try_emplace(key, static_cast<uint32_t>(mesh.positions.size()));
        if (inserted) mesh.positions.push_back(p);
        return it->second;
    };

    const BezierPatch* patches = teapot_patches();
    const double bottom = double(0.300049f);  // the data's bottom rim (z), exactly as stored
    const size_t side = size_t(n) + 1;
    std::vector<uint32_t> grid(side * side);
    for (int p = 0; p < kTeapotPatchCount; ++p) {
        for (size_t i = 0; i < side; ++i)
            for (size_t j = 0; j < side; ++j) {
                const Vec3 q = bezier_patch_point(patches[p], double(i) / n, double(j) / n);
                grid[i * side + j] = weld(to_float(Vec3d{(q.x - 0.5) * scale, (q.z - bottom) * scale, -q.y * scale}));
            }
        for (size_t i = 0; i < side - 1; ++i)
            for (size_t j = 0; j < side - 1; ++j) {
                const uint32_t a = grid[i * side + j], b = grid[(i + 1) * side + j];
                const uint32_t c = grid[(i + 1) * side + j + 1], d = grid[i * side + j + 1];
                for (const std::array<uint32_t, 3>& tri : {std::array{a, b, c}, std::array{a, c, d}})
                    if (tri[0] != tri[1] && tri[1] != tri[2] && tri[2] != tri[0]) mesh.indices.push_back(tri);
            }
    }
}

Mesh make_teapot(const Params& params) {
    Mesh mesh;
    append_teapot(mesh, int(params.whole("n")), 1.0);
    return mesh;
}

/// An icosphere of radius 1: the icosahedron, each triangle split into four
/// `subdiv` times with the new vertices pushed out onto the sphere.
/// 20 * 4^subdiv triangles, normals pointing out.
Mesh make_sphere(const Params& params) {
    // The icosahedron's 12 vertices are the cyclic permutations of (0, ±1, ±φ).
    const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3d> points;
    for (int axis = 0; axis < 3; ++axis)
        for (double a : {-1.0, 1.0})
            for (double b : {-phi, phi}) {
                double c[3] = {0, 0, 0};
                c[(axis + 1) % 3] = a;
                c[(axis + 2) % 3] = b;
                points.push_back({c[0], c[1], c[2]});
            }
    // Its 20 faces are the triples of mutually adjacent vertices (edge length 2;
    // the next-closest pairs are 2φ apart), wound to face outwards.
    std::vector<std::array<uint32_t, 3>> faces;
    auto adjacent = [&](uint32_t i, uint32_t j) { const Vec3d d = points[i] - points[j]; return dot(d, d) < 5.0; };
    for (uint32_t i = 0; i < 12; ++i)
        for (uint32_t j = i + 1; j < 12; ++j)
            for (uint32_t k = j + 1; k < 12; ++k)
                if (adjacent(i, j) && adjacent(j, k) && adjacent(i, k)) {
                    const Vec3d normal = cross(points[j] - points[i], points[k] - points[i]);
                    const Vec3d centre = points[i] + points[j] + points[k];
                    faces.push_back(dot(normal, centre) > 0 ? std::array{i, j, k} : std::array{i, k, j});
                }
    for (Vec3d& p : points) p = normalize(p);

    for (uint64_t level = 0; level < params.whole("subdiv"); ++level) {
        std::unordered_map<uint64_t, uint32_t> midpoints;  // edge (lo << 32 | hi) → new vertex
        auto midpoint = [&](uint32_t a, uint32_t b) {
            const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            const auto [it, inserted] = midpoints.try_emplace(key, static_cast<uint32_t>(points.size()));
            if (inserted) points.push_back(normalize((points[a] + points[b]) * 0.5));
            return it->second;
        };
        std::vector<std::array<uint32_t, 3>> finer;
        finer.reserve(faces.size() * 4);
        for (const auto& [a, b, c] : faces) {
            const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            finer.push_back({a, ab, ca});
            finer.push_back({b, bc, ab});
            finer.push_back({c, ca, bc});
            finer.push_back({ab, bc, ca});
        }
        faces = std::move(finer);
    }

    Mesh mesh;
    mesh.positions.reserve(points.size());
    for (const Vec3d& p : points) mesh.positions.push_back(to_float(p));
    mesh.indices = std::move(faces);
    return mesh;
}

/// cos and sin of k * 22.5° for k = 0..15 from square roots only (no libm trig).
std::pair<double, double> circle16(int k) {
    const double c1 = std::sqrt(2.0 + std::sqrt(2.0)) / 2.0;  // cos 22.5°
    const double c2 = std::sqrt(0.5);                          // cos 45°
    const double c3 = std::sqrt(2.0 - std::sqrt(2.0)) / 2.0;  // sin 22.5°
    const double first_quadrant[4][2] = {{1, 0}, {c1, c3}, {c2, c2}, {c3, c1}};
    double x = first_quadrant[k % 4][0], y = first_quadrant[k % 4][1];
    for (int q = 0; q < k / 4; ++q) {  // turn by 90°: (x, y) → (-y, x), exact
        const double t = x;
        x = -y;
        y = t;
    }
    return {x, y};
}

/// The lecture's "teapot in a stadium": a dense teapot of height 1 (tessellation n)
/// on the floor at the centre of a stadium `size` wide: a square floor (2 triangles)
/// and a 16-sided ring of stands sloping up from radius 0.36 size to 0.46 size at
/// height 0.06 size, closed by an outer wall (64 triangles). Nearly every cell of a
/// uniform grid over it is empty, and the teapot's triangles share a handful.
Mesh make_stadium(const Params& params) {
    Mesh mesh;
    append_teapot(mesh, int(params.whole("n")), 1.0 / 0.75);
    const double size = params.real("size");
    const float half = float(size / 2);
    add_quad(mesh, {-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half}, {0, 1, 0});

    const double inner = 0.36 * size, outer = 0.46 * size, height = 0.06 * size;
    auto ring_point = [&](int k, double radius, double y) {
        const auto [c, s] = circle16(k % 16);
        return to_float(Vec3d{c * radius, y, s * radius});
    };
    for (int k = 0; k < 16; ++k) {
        const Vec3 in0 = ring_point(k, inner, 0), in1 = ring_point(k + 1, inner, 0);
        const Vec3 top0 = ring_point(k, outer, height), top1 = ring_point(k + 1, outer, height);
        const Vec3 foot0 = ring_point(k, outer, 0), foot1 = ring_point(k + 1, outer, 0);
        const Vec3 middle = (in0 + in1) * 0.5f;
        add_quad(mesh, in0, in1, top1, top0, Vec3{-middle.x, float(size), -middle.z});  // stands face up and in
        add_quad(mesh, top0, top1, foot1, foot0, (foot0 + foot1) * 0.5f);                // wall faces out
    }
    return mesh;
}

// ---------------------------------------------------------------------------
// [SECTION] Tricky cases
// ---------------------------------------------------------------------------

/// A direction drawn uniformly from the unit sphere (rejection from the cube; sqrt only).
Vec3d random_unit_vector(Rng& rng) {
    for (;;) {
        const Vec3d v{rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)};
        const double length_squared = dot(v, v);
        if (length_squared > 1e-4 && length_squared <= 1.0) return v * (1.0 / std::sqrt(length_squared));
    }
}

/// n triangles, all with centroid exactly (0, 0, 0): corners a, b and -a-b for a
/// random orientation and size (largest corner distance 0.05..1). Every coordinate
/// is a multiple of 2^-20 below 2 in magnitude, so any sum of corners is exact in
/// float: the centroid is exactly 0 in whatever order it is summed.
Mesh make_same_centroid(const Params& params) {
    const double quantum = 0x1.0p-20;
    auto snap = [&](Vec3d v) {
        return Vec3d{std::round(v.x / quantum) * quantum, std::round(v.y / quantum) * quantum,
                     std::round(v.z / quantum) * quantum};
    };
    Rng rng(params.whole("seed"));
    Mesh mesh;
    const uint64_t n = params.whole("n");
    mesh.positions.reserve(3 * n);
    mesh.indices.reserve(n);
    while (mesh.triangle_count() < n) {
        const double size = rng.uniform(0.05, 1.0);
        const Vec3d a = snap(random_unit_vector(rng) * size);
        const Vec3d b = snap(random_unit_vector(rng) * (size * rng.uniform(0.3, 1.0)));
        const Vec3d normal = cross(a, b);
        if (dot(normal, normal) == 0.0) continue;  // a and b parallel after snapping: draw again
        const Vec3 fa = to_float(a), fb = to_float(b);
        mesh.add_triangle(fa, fb, -fa - fb);
    }
    return mesh;
}

/// n distinct triangles with exactly the same bounding box [-1,1] x [-0.5,0.5] x
/// [-0.75,0.75]. For each axis k, corner k lies on one face of the box and corner
/// k+1 (mod 3) on the opposite one (which one on which, drawn at random); corner k's
/// remaining coordinate, on axis k+1, is drawn inside the box. So each triangle
/// touches all six faces and stays inside: its box is the box, exactly.
Mesh make_same_box(const Params& params) {
    const Vec3 lo{-1.0f, -0.5f, -0.75f}, hi{1.0f, 0.5f, 0.75f};
    Rng rng(params.whole("seed"));
    Mesh mesh;
    const uint64_t n = params.whole("n");
    mesh.positions.reserve(3 * n);
    mesh.indices.reserve(n);
    for (uint64_t t = 0; t < n; ++t) {
        Vec3 corner[3];
        for (int k = 0; k < 3; ++k) {
            const bool flip = (rng.next_u64() >> 63) != 0;
            corner[k][k] = flip ? hi[k] : lo[k];
            corner[(k + 1) % 3][k] = flip ? lo[k] : hi[k];
        }
        for (int k = 0; k < 3; ++k) {
            const int free_axis = (k + 1) % 3;
            corner[k][free_axis] = rng.uniform(lo[free_axis], hi[free_axis]);
        }
        mesh.add_triangle(corner[0], corner[1], corner[2]);
    }
    return mesh;
}

/// n random triangles: centres uniform in [-1,1]^3, corners within ±s of the
/// centre on each axis, s = 0.005 + 0.095 u^2 for uniform u (mostly small, a few
/// up to 0.1).
Mesh make_soup(const Params& params) {
    Rng rng(params.whole("seed"));
    Mesh mesh;
    const uint64_t n = params.whole("n");
    mesh.positions.reserve(3 * n);
    mesh.indices.reserve(n);
    auto random_offset = [&](float s) {
        return Vec3{rng.uniform(-s, s), rng.uniform(-s, s), rng.uniform(-s, s)};
    };
    for (uint64_t t = 0; t < n; ++t) {
        const Vec3 centre{rng.uniform(-1.0f, 1.0f), rng.uniform(-1.0f, 1.0f), rng.uniform(-1.0f, 1.0f)};
        const float u = rng.uniform(0.0f, 1.0f);
        const float s = 0.005f + 0.095f * u * u;
        const Vec3 a = centre + random_offset(s);
        const Vec3 b = centre + random_offset(s);
        const Vec3 c = centre + random_offset(s);
        mesh.add_triangle(a, b, c);
    }
    return mesh;
}

Mesh make_empty(const Params&) { return Mesh{}; }

/// One triangle in the z = 0 plane facing +z (towards the default camera).
Mesh make_single(const Params&) {
    Mesh mesh;
    mesh.add_triangle({-1, -1, 0}, {1, -1, 0}, {0, 1, 0});
    return mesh;
}

/// The lecture's slide "two BVHs over the same 22 triangles: which is better?": 22
/// small triangles near the z = 0 plane in three clusters, 9 on the left, 8 upper
/// right and 5 lower right. A split at the median triangle along x (the longest axis)
/// cuts the lower-right cluster in two, so the halves' boxes overlap; the surface area
/// heuristic separates the clusters. Each triangle is tilted a little out of the plane
/// (corners at z = 0 and +-0.05), so no box is flat.
Mesh make_twenty_two(const Params&) {
    struct Centre {
        float x, y;
    };
    static constexpr Centre kCentres[22] = {
        // left: a jittered 3 x 3 block
        {-3.8f, -0.8f}, {-3.0f, -0.9f}, {-2.2f, -0.7f}, {-3.9f, 0.1f}, {-3.1f, 0.0f}, {-2.3f, 0.2f},
        {-3.7f, 0.9f}, {-2.9f, 0.8f}, {-2.1f, 1.0f},
        // upper right: two rows of 4
        {1.9f, 1.4f}, {2.5f, 1.3f}, {3.1f, 1.5f}, {3.7f, 1.4f}, {2.0f, 2.2f}, {2.6f, 2.3f}, {3.2f, 2.1f},
        {3.8f, 2.2f},
        // lower right: a row of 5
        {1.2f, -2.0f}, {1.8f, -2.2f}, {2.4f, -1.9f}, {3.0f, -2.1f}, {3.6f, -2.0f},
    };
    Mesh mesh;
    for (int i = 0; i < 22; ++i) {
        const Centre c = kCentres[i];
        const float s = 0.26f, flip = i % 2 ? -1.0f : 1.0f;  // alternate up- and down-pointing
        mesh.add_triangle({c.x - s, c.y - flip * 0.5f * s, 0.0f}, {c.x + s, c.y - flip * 0.5f * s, 0.05f},
                          {c.x, c.y + flip * s, -0.05f});
    }
    return mesh;
}

/// The lecture's KD-tree challenge (slide "KD 树划分的挑战"), for a ray along +x
/// through the origin's y and z: b, a long sliver, reaches from x = -2 to x = 2.5
/// and meets the ray at x = 2; a, small, meets it at x of about 1.1. A plane between
/// x = -2 and a (the median builder's first, at x = 0.25, or an SAH plane at a's near
/// side) puts b in both cells and a in the second only, so the ray, walking the first
/// cell, finds b's hit first, although a is nearer. Triangle 0 is b, 1 is a.
Mesh make_kd_challenge(const Params&) {
    Mesh mesh;
    mesh.add_triangle({2.5f, -0.25f, 0.0f}, {-2.0f, 2.0f, -0.5f}, {-2.0f, 2.0f, 0.5f});  // b
    mesh.add_triangle({1.0f, -0.5f, -0.5f}, {1.0f, 0.5f, -0.5f}, {1.2f, 0.0f, 0.5f});   // a
    return mesh;
}

// ---------------------------------------------------------------------------
// [SECTION] Big scenes
// ---------------------------------------------------------------------------

/// The lecture's 10-million-triangle scenes without a download: `mesh` (loaded as
/// load_scene loads it, through the mesh cache) repeated nx x nz times on a grid in
/// the x-z plane, copies 1.1 times the mesh's extent apart so that none overlap.
Expected<Mesh> make_instances(const Params& params) {
    const std::string& source = params.text("mesh");
    if (source.find("builtin:instances") != std::string::npos)  // (through a wave, too: copies of copies)
        return Error{"mesh= cannot be or contain another builtin:instances"};
    auto loaded = load_scene(source, params.cache, params.progress);
    if (!loaded) return Error{loaded.error()};
    return repeat_on_grid(*loaded, params.whole("nx"), params.whole("nz"), params.progress);
}

}  // namespace

Expected<Mesh> repeat_on_grid(const Mesh& one, uint64_t nx, uint64_t nz, WorkProgress* progress) {
    const uint64_t copies = nx * nz;
    if (copies * one.positions.size() > std::numeric_limits<uint32_t>::max() ||
        copies * one.indices.size() > std::numeric_limits<uint32_t>::max())
        return Error{std::to_string(copies) + " copies of " + std::to_string(one.indices.size()) +
                     " triangles are too many for 32-bit indices"};
    const Aabb box = one.bounds();
    const float step_x = 1.1f * box.extent().x, step_z = 1.1f * box.extent().z;
    Mesh mesh;
    mesh.positions.reserve(copies * one.positions.size());
    mesh.indices.reserve(copies * one.indices.size());
    for (uint64_t k = 0; k < nz; ++k)
        for (uint64_t i = 0; i < nx; ++i) {
            if (cancelled(progress)) return WorkProgress::cancelled_error();
            const Vec3 offset{float(i) * step_x, 0.0f, float(k) * step_z};
            const auto base = uint32_t(mesh.positions.size());
            for (const Vec3& p : one.positions) mesh.positions.push_back(p + offset);
            for (const auto& t : one.indices) mesh.indices.push_back({t[0] + base, t[1] + base, t[2] + base});
        }
    return mesh;
}

namespace {

// ---------------------------------------------------------------------------
// [SECTION] Moving scenes (the same triangles at every time t: a tree built at one
// time can be refitted to another)
// ---------------------------------------------------------------------------

/// cos and sin of `turns` whole turns from + - * / and floor only (no libm trig, so
/// the same bits on every machine): the angle within an eighth of a turn of a
/// multiple of a quarter turn, |x| <= pi/4, by Taylor series to x^16 and x^17 (the
/// next terms are below 3e-18), then turned by that many quarter turns exactly.
std::pair<double, double> turn_cos_sin(double turns) {
    constexpr double kHalfPi = 1.57079632679489661923;
    const double quarters = std::floor(turns * 4.0 + 0.5);
    const double x = (turns * 4.0 - quarters) * kHalfPi, x2 = x * x;
    double c = 1, s = x, term_c = 1, term_s = x;
    for (int k = 1; k <= 8; ++k) {
        term_c *= -x2 / double((2 * k - 1) * (2 * k));
        term_s *= -x2 / double((2 * k) * (2 * k + 1));
        c += term_c;
        s += term_s;
    }
    const int q = int(quarters - 4.0 * std::floor(quarters / 4.0));  // 0..3
    for (int k = 0; k < q; ++k) {  // a quarter turn: (c, s) → (-s, c), exact
        const double t = c;
        c = -s;
        s = t;
    }
    return {c, s};
}

/// A teapot flying round the Cornell box at time t: the room (static, 32 triangles
/// first) and a teapot of height 1.1 (tessellation n) whose centre circles the
/// room's vertical axis at radius 1.2, its bottom 3.4 above the floor (over the blocks), once per unit of t,
/// while it spins about its own vertical axis twice. Rays and rebuilds see one scene;
/// a BVH built at t = 0 and refitted to t sees the teapot's boxes drag the room's.
Mesh make_moving(const Params& params) {
    Mesh mesh = make_cornell(params);
    Mesh teapot;
    append_teapot(teapot, int(params.whole("n")), 1.5);
    const double t = params.real("t");
    const auto [orbit_c, orbit_s] = turn_cos_sin(t);
    const auto [spin_c, spin_s] = turn_cos_sin(2.0 * t);
    const Aabb room = mesh.bounds();
    const Vec3d centre{(double(room.lo.x) + room.hi.x) / 2.0 + 1.2 * orbit_c, 3.4,
                       (double(room.lo.z) + room.hi.z) / 2.0 + 1.2 * orbit_s};
    const auto base = uint32_t(mesh.positions.size());
    for (const Vec3& p : teapot.positions) {
        const double x = p.x, z = p.z;
        mesh.positions.push_back(
            to_float(Vec3d{centre.x + spin_c * x - spin_s * z, centre.y + p.y, centre.z + spin_s * x + spin_c * z}));
    }
    for (const auto& tri : teapot.indices) mesh.indices.push_back({tri[0] + base, tri[1] + base, tri[2] + base});
    return mesh;
}

/// A mesh whose vertices a wave lifts and lowers at time t: each vertex moves along
/// y by height·L·(g(f) - 1/2), L the mesh's longest side, f the fractional part of
/// 2x/L - t (x from the mesh's left side: a wavelength of half the longest side), and
/// g(f) = 16 f^2 (1 - f)^2 a smooth bump. One period per unit of t.
Expected<Mesh> make_wave(const Params& params) {
    const std::string& source = params.text("mesh");
    auto loaded = load_scene(source, params.cache, params.progress);
    if (!loaded) return Error{loaded.error()};
    Mesh mesh = std::move(*loaded);
    const Aabb box = mesh.bounds();
    const double longest = std::max({double(box.extent().x), double(box.extent().y), double(box.extent().z)});
    const double t = params.real("t"), height = params.real("height") * longest;
    for (Vec3& p : mesh.positions) {
        const double u = 2.0 * (double(p.x) - box.lo.x) / longest - t;
        const double f = u - std::floor(u), g = 16.0 * f * f * (1.0 - f) * (1.0 - f);
        p.y = float(double(p.y) + height * (g - 0.5));
    }
    return mesh;
}

/// An OBJ file with one of its objects (obj_objects: the faces between `o`/`g`
/// statements) made a mirror, for the ray caster's reflections (`--mirror N`).
Expected<Mesh> make_mirror(const Params& params) {
    const std::string& source = params.text("mesh");
    auto loaded = load_scene(source, params.cache, params.progress);
    if (!loaded) return Error{loaded.error()};
    // A built-in mesh is one object; an OBJ file's are its runs of faces between o / g.
    auto objects = source.rfind("builtin:", 0) == 0
                       ? Expected<std::vector<ObjObject>>(std::vector<ObjObject>{{"", 0, loaded->triangle_count()}})
                       : obj_objects(source);
    if (!objects) return Error{objects.error()};
    const uint64_t index = params.whole("object");
    if (index >= objects->size()) {
        std::string names;
        for (size_t i = 0; i < objects->size() && i < 8; ++i) {
            if (i > 0) names += ", ";
            names += std::to_string(i);
            names += ' ';
            names += (*objects)[i].name.empty() ? std::string("(unnamed)") : (*objects)[i].name;
        }
        if (objects->size() > 8) names += ", ...";
        return Error{source + " has " + std::to_string(objects->size()) + " object" +
                     (objects->size() == 1 ? "" : "s") + " (" + names + "): --mirror " + std::to_string(index) +
                     " is not one"};
    }
    Mesh mesh = std::move(*loaded);
    const ObjObject& object = (*objects)[index];
    if (object.triangle_count == 0)
        return Error{source + ": object " + std::to_string(index) + " (" + object.name +
                     ") has no faces: nothing to make a mirror"};
    if (object.first_triangle + object.triangle_count > mesh.triangle_count())
        return Error{source + ": its objects count more triangles than it loaded (a bug)"};
    mesh.mirror.assign(mesh.triangle_count(), 0);
    std::fill_n(mesh.mirror.begin() + std::ptrdiff_t(object.first_triangle), object.triangle_count, uint8_t(1));
    return mesh;
}

// ---------------------------------------------------------------------------
// [SECTION] Registry
// ---------------------------------------------------------------------------

/// A scene that cannot fail to build (all but instances), as the registry calls it.
template <Mesh (*Make)(const Params&)>
Expected<Mesh> always(const Params& params) {
    return Make(params);
}

struct BuiltinDef {
    const char* name;
    const char* summary;
    std::vector<ParamSpec> params;
    Expected<Mesh> (*make)(const Params&);
};

constexpr double kDefaultSeed = 1;
constexpr double kMaxRandomTriangles = 10'000'000;

const std::vector<BuiltinDef>& registry() {
    static const std::vector<BuiltinDef> kScenes = {
        {"cube", "the cube [-1,1]^3, 12 triangles", {}, always<make_cube>},
        {"cornell",
         "the Cornell box (room 5.56 x 5.49 x 5.59, y up, open towards +z; two blocks, the light), 32 triangles",
         {},
         always<make_cornell>},
        {"cornell-mirror",
         "the Cornell box with its tall block a mirror (reflections: render --reflections on), 32 triangles",
         {},
         always<make_cornell_mirror>},
        {"teapot",
         "Newell's teapot from its 28 Bezier patches, y up on y = 0, height 0.75; n = quads per patch side: "
         "56n^2 - 4n triangles",
         {{"n", ParamKind::Count, 1, 64, 8}},
         always<make_teapot>},
        {"sphere",
         "icosphere of radius 1 around the origin: 20 * 4^subdiv triangles",
         {{"subdiv", ParamKind::Count, 0, 7, 3}},
         always<make_sphere>},
        {"stadium",
         "teapot in a stadium: a teapot of height 1 (n as for teapot) on the floor of a stadium `size` wide "
         "(66 large triangles)",
         {{"n", ParamKind::Count, 1, 64, 12}, {"size", ParamKind::Real, 5, 100000, 100}},
         always<make_stadium>},
        {"same-centroid",
         "n random triangles whose centroids are all exactly the origin",
         {{"n", ParamKind::Count, 1, kMaxRandomTriangles, 1000}, {"seed", ParamKind::Seed, 0, 0, kDefaultSeed}},
         always<make_same_centroid>},
        {"same-box",
         "n random triangles whose bounding boxes are all exactly [-1,1] x [-0.5,0.5] x [-0.75,0.75]",
         {{"n", ParamKind::Count, 1, kMaxRandomTriangles, 1000}, {"seed", ParamKind::Seed, 0, 0, kDefaultSeed}},
         always<make_same_box>},
        {"soup",
         "n random small triangles of varying size, centres uniform in [-1,1]^3",
         {{"n", ParamKind::Count, 1, kMaxRandomTriangles, 1000}, {"seed", ParamKind::Seed, 0, 0, kDefaultSeed}},
         always<make_soup>},
        {"empty", "no triangles at all", {}, always<make_empty>},
        {"single", "one triangle in the z = 0 plane", {}, always<make_single>},
        {"kd-challenge",
         "the lecture's KD-tree challenge: a ray along +x meets b in the first cell, but a, in the second, is nearer",
         {},
         always<make_kd_challenge>},
        {"twenty-two",
         "the lecture's 22 triangles in three clusters near the z = 0 plane (two BVHs over the same triangles: "
         "which is better?)",
         {},
         always<make_twenty_two>},
        {"moving",
         "a teapot flying round the Cornell box at time t (once round per unit of t, spinning): the same "
         "triangles at every t, for refit against rebuild; n as for teapot",
         {{"t", ParamKind::Real, -1000, 1000, 0}, {"n", ParamKind::Count, 1, 64, 8}},
         always<make_moving>},
        {"wave",
         "a mesh whose vertices a wave lifts and lowers at time t (one period per unit of t; height: the wave's "
         "height over the mesh's size), e.g. builtin:wave?mesh=bunny.obj&t=0.25",
         {{"mesh", ParamKind::Source, 0, 0, 0},
          {"t", ParamKind::Real, -1000, 1000, 0},
          {"height", ParamKind::Real, 0, 1, 0.05}},
         make_wave},
        {"mirror",
         "an OBJ file with one object (the faces between its o / g statements, numbered from 0; a built-in is one "
         "object) made a mirror, "
         "e.g. builtin:mirror?mesh=room.obj&object=2 (what --mirror 2 asks for)",
         {{"mesh", ParamKind::Source, 0, 0, 0}, {"object", ParamKind::Count, 0, 1000000, 0}},
         make_mirror},
        {"instances",
         "a mesh repeated nx x nz times on a grid in the x-z plane (a 10M-triangle scene from one scan: "
         "builtin:instances?mesh=armadillo.obj&nx=6&nz=5)",
         {{"mesh", ParamKind::Source, 0, 0, 0}, {"nx", ParamKind::Count, 1, 64, 4}, {"nz", ParamKind::Count, 1, 64, 3}},
         make_instances},
    };
    return kScenes;
}

std::string known_names() {
    std::string out;
    for (const BuiltinDef& def : registry()) out += (out.empty() ? "" : ", ") + std::string(def.name);
    return out;
}

}  // namespace

Expected<std::string> scene_at_time(const std::string& source, double t) {
    constexpr std::string_view kPrefix = "builtin:";
    const size_t question = source.find('?');
    const std::string name = source.starts_with(kPrefix)
                                 ? source.substr(kPrefix.size(), question == std::string::npos ? std::string::npos
                                                                                                : question - kPrefix.size())
                                 : std::string();
    const BuiltinDef* def = nullptr;
    for (const BuiltinDef& d : registry())
        if (name == d.name) def = &d;
    std::string moving;  // the scenes with a time
    for (const BuiltinDef& d : registry())
        if (std::any_of(d.params.begin(), d.params.end(), [](const ParamSpec& p) { return p.name == std::string_view("t"); }))
            moving += (moving.empty() ? "builtin:" : ", builtin:") + std::string(d.name);
    if (!def || std::none_of(def->params.begin(), def->params.end(),
                             [](const ParamSpec& p) { return p.name == std::string_view("t"); }))
        return Error{"--time needs a moving scene (" + moving + "), not " + source};
    if (!std::isfinite(t)) return Error{"--time must be a finite number"};
    char number[32];
    const auto [end, ec] = std::to_chars(number, number + sizeof number, t);  // shortest form that reads back as t
    const std::string item = "t=" + std::string(number, end);
    if (question == std::string::npos) return source + "?" + item;
    // The items after '?' joined by '&' (a mesh= value ends at the next '&'): replace t= or add it.
    std::string out = source.substr(0, question + 1);
    bool replaced = false;
    size_t begin = question + 1;
    for (bool first = true;; first = false) {
        const size_t amp = source.find('&', begin);
        std::string part = source.substr(begin, amp == std::string::npos ? std::string::npos : amp - begin);
        if (part.starts_with("t=")) {
            part = item;
            replaced = true;
        }
        out += (first ? "" : "&") + part;
        if (amp == std::string::npos) break;
        begin = amp + 1;
    }
    if (!replaced) out += (out.back() == '?' ? "" : "&") + item;
    return out;
}

std::optional<double> scene_time(const std::string& source) {
    if (!scene_at_time(source, 0.0)) return std::nullopt;  // not a moving scene
    const size_t question = source.find('?');
    if (question == std::string::npos) return 0.0;
    for (size_t begin = question + 1; begin <= source.size();) {
        const size_t amp = std::min(source.find('&', begin), source.size());
        const std::string_view part = std::string_view(source).substr(begin, amp - begin);
        if (part.starts_with("t=")) {
            double t = 0;
            if (!parse_real(part.substr(2), t)) return std::nullopt;
            return t;
        }
        begin = amp + 1;
    }
    return 0.0;
}

Expected<Mesh> make_builtin(const std::string& spec, WorkProgress* progress) {
    return make_builtin(spec, progress, default_mesh_cache());
}

Expected<Mesh> make_builtin(const std::string& spec, WorkProgress* progress, MeshCache cache) {
    const std::string full = "builtin:" + spec;
    const size_t question = spec.find('?');
    const std::string_view name = std::string_view(spec).substr(0, question);
    const std::string_view query =
        question == std::string::npos ? std::string_view() : std::string_view(spec).substr(question + 1);

    const BuiltinDef* def = nullptr;
    for (const BuiltinDef& d : registry())
        if (name == d.name) def = &d;
    if (!def) {
        const std::string what = name.empty() ? "no built-in scene name given" : "unknown built-in scene '" + std::string(name) + "'";
        return Error{full + ": " + what + "; known: " + known_names()};
    }

    auto fail = [&](const std::string& reason) {
        const std::string accepted =
            def->params.empty() ? std::string(def->name) + " takes no parameters"
                                : std::string(def->name) + " accepts " + describe(def->params);
        return Error{full + ": " + reason + "; " + accepted};
    };
    auto params = parse_params(def->params, query, fail);
    if (!params) return Error{params.error()};
    params->progress = progress;
    params->cache = cache;

    // The scene as error messages name it: a long source (one nesting others) cut short.
    const std::string shown = full.size() > 200 ? full.substr(0, 200) + "..." : full;
    // Scenes made from scenes (mesh=) nest on this thread's stack; a source nesting
    // thousands deep must be refused, not exhaust the stack or memory.
    thread_local int nesting = 0;
    constexpr int kMaxNesting = 4;
    if (nesting >= kMaxNesting)
        return Error{shown + ": scenes made from scenes (mesh=) nest at most " +
                     std::to_string(kMaxNesting) + " deep"};
    struct Nested {
        Nested() { ++nesting; }
        ~Nested() { --nesting; }
    } nested;

    try {
        auto mesh = def->make(*params);
        if (!mesh && mesh.error() == WorkProgress::cancelled_error().message) return mesh;  // as it is: the caller knows it
        if (!mesh) return Error{shown + ": " + mesh.error()};
        mesh->name = full;
        return mesh;
    } catch (const std::exception& e) {  // e.g. std::bad_alloc for a huge n
        return Error{shown + ": cannot build: " + e.what()};
    }
}

const std::vector<BuiltinInfo>& builtin_scenes() {
    static const std::vector<BuiltinInfo> kInfo = [] {
        std::vector<BuiltinInfo> info;
        for (const BuiltinDef& def : registry())
            info.push_back({def.name, std::string(def.summary) + "; " + describe(def.params)});
        return info;
    }();
    return kInfo;
}

}  // namespace accelviz
