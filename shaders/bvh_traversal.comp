#version 430
// The binary BVH traversed on the GPU: one invocation per pixel, a fixed stack, the
// lecture's algorithm 2 (both children's boxes tested, the nearer visited first, a
// node whose box starts beyond the closest hit skipped). The same arithmetic as the
// CPU's Bvh::walk, operation for operation and `precise` (no fused multiply-add), so
// that both find the same triangle at the same t: the slab test widened by 2^-16
// (core/math/box_test.h), Moller-Trumbore with its double solve of ill-conditioned
// candidates and the own-box rule (core/geometry/triangle.h), ties broken by the
// lower triangle id. (Bit for bit where float and double division round correctly,
// as on llvmpipe; GLSL itself does not promise it.)
//
// Buffers (std430, plain words, so the layout is the CPU's arrays as they are):
//   0 nodes: 8 words each, the box lo.xyz hi.xyz (float bits), first, count (count > 0: a leaf)
//   1 triangles in leaf order: 9 floats each, p0, edge1 = p1 - p0, edge2 = p2 - p0
//   2 prim_ids: the triangle id of each leaf slot
//   3 rays, one per pixel: origin, dir, 1/dir (9 floats; the camera's, made on the CPU)
//   4 results, 6 words per pixel: triangle id (or ~0), t (float bits), colour (RGBA8),
//     the loop's iterations (nodes visited), the deepest the stack got, triangle tests

layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Nodes { uint node_words[]; };
layout(std430, binding = 1) readonly buffer Triangles { float tri_floats[]; };
layout(std430, binding = 2) readonly buffer PrimIds { uint prim_ids[]; };
layout(std430, binding = 3) readonly buffer Rays { float ray_floats[]; };
layout(std430, binding = 4) writeonly buffer Results { uint results[]; };

uniform ivec2 u_size;
uniform int u_node_count;
uniform vec3 u_background;  // 0..255

const uint kNoHit = 0xffffffffu;
const int kStackSize = 64;
const float kMargin = 1.0 / 65536.0;
const float kDetShareForFloat = 1.0 / 64.0;           // as core/geometry/triangle.h
const double kDetShareForDouble = 1.0LF / 4294967296.0LF;
const float kSmallestNormal = 1.17549435e-38;  // FLT_MIN
const float kLargestFloat = 3.40282347e38;     // FLT_MAX

float inf() { return uintBitsToFloat(0x7f800000u); }

float node_plane(uint node, int k) { return uintBitsToFloat(node_words[node * 8u + uint(k)]); }

// The ray's per-ray constants, as BoxTestRay.
vec3 g_origin, g_dir, g_near_inv, g_far_inv;
ivec3 g_near_plane, g_far_plane;

// The widened slab interval of box (lo = planes 0..2, hi = 3..5) clipped to [t_min, t_max].
void slab(float planes[6], float t_min, float t_max, out float enter, out float exit_) {
    precise float e = t_min;
    precise float x = t_max;
    for (int axis = 0; axis < 3; ++axis) {
        precise float t_near = (planes[g_near_plane[axis]] - g_origin[axis]) * g_near_inv[axis];
        precise float t_far = (planes[g_far_plane[axis]] - g_origin[axis]) * g_far_inv[axis];
        e = t_near > e ? t_near : e;
        x = t_far < x ? t_far : x;
    }
    enter = e;
    exit_ = x;
}

void node_slab(uint node, float t_min, float t_max, out float enter, out float exit_) {
    float planes[6];
    for (int k = 0; k < 6; ++k) planes[k] = node_plane(node, k);
    slab(planes, t_min, t_max, enter, exit_);
}

vec3 cross_(vec3 a, vec3 b) {
    precise vec3 c = vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
    return c;
}
float dot_(vec3 a, vec3 b) {
    precise float d = a.x * b.x + a.y * b.y + a.z * b.z;
    return d;
}

dvec3 cross_d(dvec3 a, dvec3 b) {
    precise dvec3 c = dvec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
    return c;
}
double dot_d(dvec3 a, dvec3 b) {
    precise double d = a.x * b.x + a.y * b.y + a.z * b.z;
    return d;
}

// Moller-Trumbore on leaf slot k with the own-box rule; true and t for a hit in [0, t_max].
bool intersect(uint k, float t_max, out float t_hit) {
    const uint b = k * 9u;
    const vec3 p0 = vec3(tri_floats[b], tri_floats[b + 1u], tri_floats[b + 2u]);
    const vec3 e1 = vec3(tri_floats[b + 3u], tri_floats[b + 4u], tri_floats[b + 5u]);
    const vec3 e2 = vec3(tri_floats[b + 6u], tri_floats[b + 7u], tri_floats[b + 8u]);
    t_hit = 0.0;
    precise vec3 pvec = cross_(g_dir, e2);
    precise float det = dot_(e1, pvec);
    if (det == 0.0) return false;
    precise float inv_det = 1.0 / det;
    precise vec3 tvec = g_origin - p0;
    precise float u = dot_(tvec, pvec) * inv_det;
    precise vec3 qvec = cross_(tvec, e1);
    precise float v = dot_(g_dir, qvec) * inv_det;
    precise float t = dot_(e2, qvec) * inv_det;
    precise float uv = u + v;
    if (!(u >= 0.0 && v >= 0.0 && uv <= 1.0)) return false;
    // det small beside its terms: solved again in double (finish_moller_trumbore).
    precise float terms = abs(e1.x) * (abs(g_dir.y * e2.z) + abs(g_dir.z * e2.y)) +
                          abs(e1.y) * (abs(g_dir.z * e2.x) + abs(g_dir.x * e2.z)) +
                          abs(e1.z) * (abs(g_dir.x * e2.y) + abs(g_dir.y * e2.x));
    precise float det_floor = kDetShareForFloat * terms;
    if (!(abs(det) >= det_floor && terms >= kSmallestNormal && terms <= kLargestFloat)) {
        const dvec3 d = dvec3(g_dir), a = dvec3(e1), c = dvec3(e2);
        precise dvec3 tv = dvec3(g_origin) - dvec3(p0);
        precise dvec3 pv = cross_d(d, c);
        precise double det_d = dot_d(a, pv);
        precise double terms_d = abs(a.x) * (abs(d.y * c.z) + abs(d.z * c.y)) +
                                 abs(a.y) * (abs(d.z * c.x) + abs(d.x * c.z)) +
                                 abs(a.z) * (abs(d.x * c.y) + abs(d.y * c.x));
        precise double det_floor_d = kDetShareForDouble * terms_d;
        if (!(abs(det_d) >= det_floor_d)) return false;
        precise dvec3 qv = cross_d(tv, a);
        precise double u_d = dot_d(tv, pv) / det_d;
        precise double v_d = dot_d(d, qv) / det_d;
        precise double t_d = dot_d(c, qv) / det_d;
        precise double uv_d = u_d + v_d;
        t = float(t_d);
        if (!(u_d >= 0.0 && v_d >= 0.0 && uv_d <= 1.0)) return false;
    }
    // The own-box rule: the triangle's box, the ray's widened interval through it.
    precise vec3 p1 = p0 + e1;
    precise vec3 p2 = p0 + e2;
    const vec3 lo = min(min(p0, p1), p2), hi = max(max(p0, p1), p2);
    float planes[6] = float[6](lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
    float own_enter, own_exit;
    slab(planes, -inf(), inf(), own_enter, own_exit);
    if (!(own_enter <= own_exit) || !(own_enter < inf()) || !(own_exit > -inf())) return false;
    t = t < own_enter ? own_enter : (t > own_exit ? own_exit : t);
    t_hit = t;
    return t >= 0.0 && t <= t_max;
}

void main() {
    const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= u_size.x || pixel.y >= u_size.y) return;
    const uint index = uint(pixel.y * u_size.x + pixel.x);
    const uint r = index * 9u;
    g_origin = vec3(ray_floats[r], ray_floats[r + 1u], ray_floats[r + 2u]);
    g_dir = vec3(ray_floats[r + 3u], ray_floats[r + 4u], ray_floats[r + 5u]);
    const vec3 dir_inv = vec3(ray_floats[r + 6u], ray_floats[r + 7u], ray_floats[r + 8u]);
    precise vec3 near_inv = dir_inv * (1.0 - kMargin);
    precise vec3 far_inv = dir_inv * (1.0 + kMargin);
    g_near_inv = near_inv;
    g_far_inv = far_inv;
    for (int axis = 0; axis < 3; ++axis) {
        const bool negative = (floatBitsToUint(g_dir[axis]) >> 31) != 0u;
        g_near_plane[axis] = axis + (negative ? 3 : 0);
        g_far_plane[axis] = axis + (negative ? 0 : 3);
    }

    uint best_tri = kNoHit, best_slot = 0u;
    float best_t = inf();
    uint iterations = 0u, deepest = 0u, tests = 0u;
    uint stack_node[kStackSize];
    float stack_enter[kStackSize];
    int top = 0;
    if (u_node_count > 0) {
        float enter, exit_;
        node_slab(0u, 0.0, inf(), enter, exit_);
        uint current = 0u;
        bool walking = enter <= exit_;
        while (walking) {
            ++iterations;
            const uint first = node_words[current * 8u + 6u], count = node_words[current * 8u + 7u];
            bool descended = false;
            if (count > 0u) {
                for (uint k = first; k < first + count; ++k) {
                    ++tests;
                    float t;
                    if (intersect(k, best_t, t) && (t < best_t || (t == best_t && prim_ids[k] < best_tri))) {
                        best_tri = prim_ids[k];
                        best_slot = k;
                        best_t = t;
                    }
                }
            } else {
                float a_enter, a_exit, b_enter, b_exit;
                node_slab(first, 0.0, inf(), a_enter, a_exit);
                node_slab(first + 1u, 0.0, inf(), b_enter, b_exit);
                const bool keep_left = a_enter <= a_exit && !(a_enter > best_t);
                const bool keep_right = b_enter <= b_exit && !(b_enter > best_t);
                if (keep_left && keep_right) {
                    if (top < kStackSize) {
                        // Nearer first (the left on a tie); the other waits.
                        const bool right_first = b_enter < a_enter;
                        stack_node[top] = right_first ? first : first + 1u;
                        stack_enter[top] = right_first ? a_enter : b_enter;
                        ++top;
                        deepest = max(deepest, uint(top));
                        current = right_first ? first + 1u : first;
                        descended = true;
                    }
                } else if (keep_left) {
                    current = first;
                    descended = true;
                } else if (keep_right) {
                    current = first + 1u;
                    descended = true;
                }
            }
            if (descended) continue;
            // The next deferred node, unless the closest hit has overtaken it.
            walking = false;
            while (top > 0) {
                --top;
                if (stack_enter[top] > best_t) continue;
                current = stack_node[top];
                walking = true;
                break;
            }
        }
    }

    uint colour;
    if (best_tri != kNoHit) {
        // Headlight shading (core/render/shading.h): |cos| between the normal and the ray.
        const uint b = best_slot * 9u;
        const vec3 e1 = vec3(tri_floats[b + 3u], tri_floats[b + 4u], tri_floats[b + 5u]);
        const vec3 e2 = vec3(tri_floats[b + 6u], tri_floats[b + 7u], tri_floats[b + 8u]);
        const vec3 n = cross_(e1, e2);
        const float nn = length(n) * length(g_dir);
        const float c = nn > 0.0 ? abs(dot_(n, g_dir)) / nn : 0.0;
        const float k = 0.15 + 0.85 * c;
        const uvec3 rgb = uvec3(round(vec3(225.0, 205.0, 170.0) * k));
        colour = rgb.r | (rgb.g << 8) | (rgb.b << 16) | (255u << 24);
    } else {
        colour = uint(u_background.r) | (uint(u_background.g) << 8) | (uint(u_background.b) << 16) | (255u << 24);
    }
    const uint o = index * 6u;
    results[o] = best_tri;
    results[o + 1u] = floatBitsToUint(best_t);
    results[o + 2u] = colour;
    results[o + 3u] = iterations;
    results[o + 4u] = deepest;
    results[o + 5u] = tests;
}
