#include "core/query/inside_slice.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include <tbb/parallel_for.h>

#include "core/accel/bvh.h"
#include "core/query/inside.h"
#include "core/traversal/observers.h"

namespace accelviz {

Vec3 InsideSlice::sample(int c, int r) const {
    Vec3 p(0, 0, 0);
    p[spec.axis] = position;
    p[u_axis] = u_lo + (float(c) + 0.5f) / float(spec.columns) * (u_hi - u_lo);
    p[v_axis] = v_hi - (float(r) + 0.5f) / float(spec.rows) * (v_hi - v_lo);
    return p;
}

std::array<Vec3, 4> InsideSlice::corners() const {
    std::array<Vec3, 4> out;
    const float us[4] = {u_lo, u_hi, u_hi, u_lo}, vs[4] = {v_lo, v_lo, v_hi, v_hi};
    for (int i = 0; i < 4; ++i) {
        out[i][spec.axis] = position;
        out[i][u_axis] = us[i];
        out[i][v_axis] = vs[i];
    }
    return out;
}

bool has_crossing_count(const Accelerator& accel) {
    return accel.type() == AccelType::Naive || structure_if<Bvh>(accel) != nullptr;
}

Expected<InsideSlice> inside_slice(const Accelerator& accel, const Mesh& mesh, const SliceSpec& spec,
                                   const std::atomic<bool>* cancel) {
    if (spec.axis < 0 || spec.axis > 2) return Error{"slice axis: x, y or z"};
    if (!(spec.fraction >= 0.0f && spec.fraction <= 1.0f)) return Error{"slice position: between 0 and 1"};
    if (spec.columns < 1 || spec.rows < 1 || spec.columns > 4096 || spec.rows > 4096)
        return Error{"slice size: 1 to 4096 samples each way"};
    if (!has_crossing_count(accel))
        return Error{"the inside/outside slice counts crossings through naive or the binary BVH; the " +
                     accel.name() + " stops at the first hit"};
    InsideSlice out;
    out.spec = spec;
    // Seen from +axis with the other two as right and up: x -> (z, y), y -> (x, z), z -> (x, y).
    static constexpr int kU[3] = {2, 0, 0}, kV[3] = {1, 2, 1};
    out.u_axis = kU[spec.axis];
    out.v_axis = kV[spec.axis];
    const Aabb box = mesh.bounds();
    if (box.empty()) return Error{"the scene has no triangles to slice"};
    const Vec3 margin = box.extent() * 0.1f;
    out.position = box.lo[spec.axis] + spec.fraction * (box.hi[spec.axis] - box.lo[spec.axis]);
    out.u_lo = box.lo[out.u_axis] - margin[out.u_axis];
    out.u_hi = box.hi[out.u_axis] + margin[out.u_axis];
    out.v_lo = box.lo[out.v_axis] - margin[out.v_axis];
    out.v_hi = box.hi[out.v_axis] + margin[out.v_axis];
    out.votes.assign(size_t(spec.columns) * size_t(spec.rows), 0);

    const Bvh* bvh = structure_if<Bvh>(accel);
    const TriangleArray triangles = bvh ? TriangleArray{} : make_triangles(mesh);
    std::vector<Counters> per_row(size_t(spec.rows));
    std::atomic<bool> cancelled{false};
    tbb::parallel_for(0, spec.rows, [&](int r) {
        if (cancel && cancel->load(std::memory_order_relaxed)) {
            cancelled = true;
            return;
        }
        Counters& counters = per_row[size_t(r)];
        for (int c = 0; c < spec.columns; ++c) {
            const InsideTest test = inside_by_parity(out.sample(c, r), [&](const Ray& ray) {
                CountingObserver counter;
                const uint32_t n =
                    bvh ? count_crossings(*bvh, ray, counter) : count_crossings_brute_force(triangles, ray, counter);
                counters += counter.counters;
                return n;
            });
            out.votes[size_t(r) * size_t(spec.columns) + size_t(c)] = uint8_t(test.votes_inside);
        }
    });
    if (cancelled) return Error{"cancelled"};
    for (const Counters& c : per_row) {
        out.nodes_visited += c.nodes_visited;
        out.triangle_tests += c.triangle_tests;
    }
    out.rays = 3ull * out.votes.size();
    return out;
}

Rgb slice_colour(int votes) {
    switch (votes) {
        case 3: return {235, 150, 60};
        case 2: return {240, 200, 150};
        case 1: return {120, 130, 190};
        default: return {30, 40, 70};
    }
}

Image slice_view(const InsideSlice& slice, int width, int height) {
    Image out(width, height);
    fill_rect(out, 0, 0, width, height, {16, 18, 24});
    // The rectangle at its own proportions, as large as fits, centred.
    const int cols = slice.spec.columns, rows = slice.spec.rows;
    const double aspect = double(slice.u_hi - slice.u_lo) / std::max(1e-30, double(slice.v_hi - slice.v_lo));
    const int fit_w = std::max(1, int(std::min(double(width), height * aspect)));
    const int fit_h = std::max(1, int(std::min(double(height), width / aspect)));
    const int x0 = (width - fit_w) / 2, y0 = (height - fit_h) / 2;
    for (int y = 0; y < fit_h; ++y)
        for (int x = 0; x < fit_w; ++x) {
            const int c = std::min(cols - 1, x * cols / fit_w);
            const int r = std::min(rows - 1, y * rows / fit_h);
            out.at(x0 + x, y0 + y) = slice_colour(slice.votes[size_t(r) * size_t(cols) + size_t(c)]);
        }
    const int s = std::max(1, height / 240);
    const char* names = "xyz";
    char title[160];
    std::snprintf(title, sizeof title, "inside / outside: the plane %c = %.4g (right %c, up %c)", names[slice.spec.axis],
                  slice.position, names[slice.u_axis], names[slice.v_axis]);
    const int y = 4 * s + draw_label(out, 4 * s, 4 * s, title, s + 1) + s;
    size_t split = 0;
    for (uint8_t v : slice.votes) split += (v == 1 || v == 2) ? 1 : 0;
    char detail[200];
    std::snprintf(detail, sizeof detail, "%zu points x 3 rays; odd crossings = inside; %zu points with split votes",
                  slice.votes.size(), split);
    draw_label(out, 4 * s, y, detail, s);
    // The legend: four swatches, bottom left.
    const char* meanings[4] = {"outside (0 of 3)", "1 of 3", "2 of 3", "inside (3 of 3)"};
    int x = 4 * s;
    const int box = 10 * s, base = height - box - 6 * s;
    for (int votes = 0; votes <= 3; ++votes) {
        fill_rect(out, x - s, base - s, box + 2 * s, box + 2 * s, {255, 255, 255});
        fill_rect(out, x, base, box, box, slice_colour(votes));
        x += box + 3 * s;
        int w = 0, h = 0;
        text_size(meanings[votes], s, &w, &h);
        draw_label(out, x, base - (h - box) / 2 - 2 * s, meanings[votes], s);
        x += w + 10 * s;
    }
    return out;
}

}  // namespace accelviz
