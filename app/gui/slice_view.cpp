#include "app/gui/slice_view.h"

#include <chrono>
#include <cstdio>

namespace accelviz {

void SliceView::update(const AppState& state, const std::shared_ptr<const LoadedScene>& scene, bool wait) {
    if (!state.view.slice || !scene) {
        if (cancel_) *cancel_ = true;
        job_.take();  // a finished slice nobody wants (left, it would count as pending work)
        requested_scene_.reset();
        requested_spec_.reset();
        shown_.reset();
        status_.clear();
        return;
    }
    SliceSpec spec;
    spec.axis = state.view.slice_axis;
    spec.fraction = state.view.slice_at;
    spec.columns = spec.rows = kWindowSliceSamples;
    if (requested_scene_ != scene || !requested_spec_ || *requested_spec_ != spec) {
        if (cancel_) *cancel_ = true;  // the running slice is stale
        cancel_ = std::make_shared<std::atomic<bool>>(false);
        requested_scene_ = scene;
        requested_spec_ = spec;
        if (!shown_) status_ = "computing the slice ...";
        job_.submit([scene, spec, cancel = cancel_] {
            Result out;
            out.scene = scene;
            out.spec = spec;
            const auto start = std::chrono::steady_clock::now();
            auto slice = inside_slice(*scene->accel, *scene->mesh, spec, cancel.get());
            out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
            if (slice) out.slice = std::make_shared<const InsideSlice>(std::move(*slice));
            else out.error = slice.error();
            return out;
        });
    }
    if (wait) job_.wait();
    if (auto done = job_.take()) take(*done);
}

void SliceView::take(const Result& done) {
    if (done.scene != requested_scene_ || !requested_spec_ || done.spec != *requested_spec_) return;  // stale
    if (!done.slice) {
        shown_.reset();
        if (done.error != "cancelled") status_ = done.error;
        dirty_ = true;
        return;
    }
    shown_ = done.slice;
    char text[160];
    std::snprintf(text, sizeof text, "%dx%d points, %llu rays: %.0f ms", shown_->spec.columns, shown_->spec.rows,
                  (unsigned long long)shown_->rays, done.ms);
    status_ = text;
    dirty_ = true;
}

void SliceView::draw_3d(Renderer& renderer) {
    if (dirty_) {
        if (!quads_) quads_ = std::make_unique<ColouredBuffer>();
        std::vector<ColouredQuad> quads;
        if (shown_) {
            // One quad per run of samples with the same vote along a row.
            const InsideSlice& s = *shown_;
            const int cols = s.spec.columns, rows = s.spec.rows;
            const float du = (s.u_hi - s.u_lo) / float(cols), dv = (s.v_hi - s.v_lo) / float(rows);
            auto corner = [&](float u, float v) {
                Vec3 p(0, 0, 0);
                p[s.spec.axis] = s.position;
                p[s.u_axis] = u;
                p[s.v_axis] = v;
                return p;
            };
            for (int r = 0; r < rows; ++r) {
                const float v_top = s.v_hi - float(r) * dv, v_bottom = v_top - dv;
                for (int c = 0; c < cols;) {
                    const uint8_t votes = s.votes[size_t(r) * size_t(cols) + size_t(c)];
                    int end = c + 1;
                    while (end < cols && s.votes[size_t(r) * size_t(cols) + size_t(end)] == votes) ++end;
                    const float u0 = s.u_lo + float(c) * du, u1 = s.u_lo + float(end) * du;
                    const Rgb colour = slice_colour(votes);
                    const uint8_t alpha = votes == 0 ? 90 : 200;  // the outside fainter: the mesh shows through
                    quads.push_back({{corner(u0, v_bottom), corner(u1, v_bottom), corner(u1, v_top), corner(u0, v_top)},
                                     {colour.r, colour.g, colour.b, alpha}});
                    c = end;
                }
            }
        }
        quads_->upload_quads(quads);
        dirty_ = false;
    }
    if (quads_ && shown_) renderer.draw_quads(*quads_);
}

}  // namespace accelviz
