#include "app/gui/scaling_panel.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include <imgui.h>

#include "app/gui/panel_widgets.h"
#include "app/platform/gl_lookup.h"
#include "core/render/chart.h"

namespace accelviz {

namespace {

/// The structures the panel offers (naive would test every triangle for every ray).
constexpr auto kOffered = kScalingStructures;

const char* offered_label(AccelType type) {
    switch (type) {
        case AccelType::Bvh: return "BVH";
        case AccelType::Kd: return "KD tree";
        case AccelType::Grid: return "grid";
        case AccelType::Octree: return "octree";
        default: return "?";
    }
}

/// 10k, 4.0M: a triangle count for a projector.
std::string triangles_text(double n) {
    return n >= 1e6 ? text_of("%.1fM", n / 1e6) : text_of("%.0fk", n / 1e3);
}

}  // namespace

ScalingPanel::~ScalingPanel() {
    if (progress_) progress_->cancel();
    if (gl_) gl_->answered.notify_all();
}

void ScalingPanel::start(const ScalingSettings& settings, std::shared_ptr<const LoadedScene> scene, int width,
                         int height, const std::string& gl_name) {
    if (progress_) progress_->cancel();  // an older measurement still running is not wanted
    requested_mesh_ = scene->mesh;
    error_.clear();
    progress_ = std::make_shared<WorkProgress>();
    gl_ = std::make_shared<GlFrameRequest>();
    if (timer_) timer_->forget();  // the new job's meshes may sit where the old job's did
    job_.submit([settings, scene = std::move(scene), progress = progress_, gl = gl_, repeat = repeat, width, height,
                 gl_name, wake = on_frame_wanted] {
        Result result{settings, std::nullopt, ""};
        ScalingOptions options;
        options.structures.clear();
        for (AccelType type : settings.structures) {
            // The scene's own parameters for its structure, the defaults for the others.
            AccelConfig config = scene->accel_config.type == type && scene->accel_config.structure_file.empty()
                                     ? scene->accel_config
                                     : AccelConfig{};
            config.type = type;
            options.structures.push_back(config);
        }
        options.max_triangles = uint64_t(settings.max_triangles);
        options.width = width;
        options.height = height;
        options.repeat = repeat;
        options.progress = progress.get();
        options.on_step = [&gl](const std::string& step) {
            std::lock_guard lock(gl->mutex);
            gl->step = step;
        };
        // OpenGL's frames are drawn by the UI thread: ask, then wait for the answer
        // (or for Cancel).
        options.gl_raster_ms = [&gl, &progress, &wake](const Mesh& mesh, const Camera& camera) -> Expected<double> {
            std::unique_lock lock(gl->mutex);
            gl->mesh = &mesh;
            gl->camera = camera;
            gl->ms.reset();
            if (wake) wake();
            while (!gl->ms) {
                if (progress->cancelled()) {
                    gl->mesh = nullptr;
                    return WorkProgress::cancelled_error();
                }
                gl->answered.wait_for(lock, std::chrono::milliseconds(50));
            }
            return *gl->ms;
        };
        Expected<ScalingResult> measured = Error{"not measured"};
        try {
            measured = measure_scaling(*scene->mesh, options);
        } catch (const std::bad_alloc&) {  // a scene the memory budget's estimate let through
            measured = Error{"out of memory; choose fewer triangles"};
        }
        if (measured) {
            measured->mesh_name = scene->source;
            measured->gl_renderer = gl_name;
            result.scaling = std::move(*measured);
        } else {
            result.error = measured.error();
        }
        return result;
    });
}

bool ScalingPanel::serve_gl_frame(Renderer& renderer) {
    if (!gl_) return false;
    std::lock_guard lock(gl_->mutex);
    if (!gl_->mesh || gl_->ms) return false;
    if (!timer_) timer_ = std::make_unique<RasterTimer>(renderer);
    gl_->ms = timer_->frame_ms(*gl_->mesh, *gl_->camera);
    gl_->mesh = nullptr;
    gl_->answered.notify_all();
    return true;
}

void ScalingPanel::cancel() {
    if (job_.busy() && progress_) {
        progress_->cancel();
        requested_mesh_.reset();  // not measured: the next showing measures again
    }
}

void ScalingPanel::take_finished() {
    auto done = job_.take();
    if (!done) return;
    timer_.reset();  // the biggest scene's copy on the GPU is not needed any more
    if (done->scaling) {
        result_ = std::move(*done);
        ++result_generation_;
    } else if (done->error != WorkProgress::cancelled_error().message) error_ = done->error;
}

void ScalingPanel::update(const AppState& state, const std::shared_ptr<const LoadedScene>& scene, Renderer& renderer,
                          int view_width, int view_height, bool shown, bool wait) {
    if (!shown || !scene || view_width <= 0 || view_height <= 0) {
        cancel();  // a measurement nobody sees is not wanted
        if (!job_.busy()) take_finished();
        return;
    }
    if (requested_mesh_.lock() != scene->mesh || measure_again_) {
        measure_again_ = false;
        start(state.scaling, scene, view_width, view_height, gl_description());
    }
    serve_gl_frame(renderer);
    while (wait && job_.busy())
        if (!serve_gl_frame(renderer)) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (!job_.busy()) take_finished();
}

void ScalingPanel::draw(AppState& state, float width, bool lecture) {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextUnformatted("Frame time against triangles: measured here, now");
    if (!lecture)
        ImGui::TextDisabled(
            "The scene's mesh repeated 1, 2, 4, ... times, each scene seen whole: rasterizing must touch every "
            "triangle, ray casting through a hierarchy need not.");
    // The settings: a new measurement on the button, not on every drag.
    ScalingSettings& s = state.scaling;
    float max_millions = float(s.max_triangles / 1e6);
    ImGui::SetNextItemWidth(std::min(width, 14.0f * ImGui::GetFontSize()));
    if (ImGui::SliderFloat("up to (million triangles)", &max_millions, 0.01f, 20.0f, "%.2f",
                           ImGuiSliderFlags_Logarithmic))
        s.max_triangles = std::round(std::clamp(double(max_millions) * 1e6, 1e4, 2e7));
    for (size_t i = 0; i < std::size(kOffered); ++i) {
        const AccelType type = kOffered[i];
        const auto at = std::find(s.structures.begin(), s.structures.end(), type);
        bool on = at != s.structures.end();
        if (i > 0) ImGui::SameLine();
        if (ImGui::Checkbox(offered_label(type), &on)) {
            if (on) s.structures.push_back(type);
            else if (s.structures.size() > 1) s.structures.erase(at);  // one at least
        }
    }
    if (job_.busy()) {
        std::string step;
        if (gl_) {
            std::lock_guard lock(gl_->mutex);
            step = gl_->step;
        }
        ImGui::Text("Measuring: %s ...", step.c_str());
        // Always a line here, so that the Cancel button below stays where it is.
        if (!lecture)
            ImGui::TextDisabled("%s", step.find("OpenGL") != std::string::npos
                                          ? "(the window pauses while OpenGL draws each of these frames)"
                                          : " ");
        progress_with_cancel(progress_.get(), width);
    } else {
        const bool changed = result_ && !(result_->settings.max_triangles == s.max_triangles &&
                                          result_->settings.structures == s.structures);
        if (ImGui::Button(changed ? "Measure with these settings" : "Measure again")) measure_again_ = true;
    }
    if (!error_.empty() && !job_.busy()) error_line("Could not measure", error_);
    if (const ScalingResult* r = measured()) {
        draw_chart(*r, width);
        if (!r->points.empty()) {
            const ScalingPoint& last = r->points.back();
            ImGui::Text("At %s triangles, rasterizing: %s%.0f ms on the CPU",
                        triangles_text(double(last.triangles)).c_str(),
                        last.gl_raster_ms ? text_of("%.0f ms by OpenGL, ", *last.gl_raster_ms).c_str() : "",
                        last.cpu_raster_ms);
            for (size_t k = 0; k < last.cast_ms.size() && k < r->structures.size(); ++k)
                ImGui::Text("  ray cast through the %s: %.0f ms (built in %s)", offered_label(r->structures[k].type),
                            last.cast_ms[k],
                            (last.build_ms[k] < 1e3 ? text_of("%.0f ms", last.build_ms[k])
                                                    : text_of("%.1f s", last.build_ms[k] / 1e3))
                                .c_str());
        }
        if (!r->stopped_early.empty()) ImGui::TextDisabled("%s", r->stopped_early.c_str());
        if (!lecture)
            ImGui::TextDisabled("Frames of %d x %d pixels; ray casts on %d threads, the CPU rasterizer on one; "
                                "OpenGL: %s.",
                                r->width, r->height, r->threads, r->gl_renderer.c_str());
    }
    ImGui::PopTextWrapPos();
}

void ScalingPanel::draw_chart(const ScalingResult& r, float width) {
    // The chart `render --view scaling` draws, without its title (the panel's heading)
    // and with its legend as ImGui text below, in the window's font.
    LineChart chart = scaling_chart(r);
    chart.title.clear();
    chart.y_label = "ms per frame";  // the size and threads: in the text below
    chart.legend = false;
    const int text_scale = std::max(1, int(std::lround(ImGui::GetFontSize() / 10.0f)));
    chart.text_scale = text_scale;
    const int w = std::max(64, int(width)), h = std::max(48, int(0.7f * width));
    if (!chart_texture_ || charted_generation_ != result_generation_ || charted_width_ != w ||
        charted_text_scale_ != text_scale) {
        Image image(w, h);
        draw_line_chart(image, 0, 0, w, h, chart);
        if (!chart_texture_) chart_texture_ = std::make_unique<Texture>();
        chart_texture_->upload(image, /*smooth=*/true);
        charted_generation_ = result_generation_;
        charted_width_ = w;
        chart_height_ = h;
        charted_text_scale_ = text_scale;
    }
    ImGui::Image(reinterpret_cast<ImTextureID>(intptr_t(chart_texture_->id())), ImVec2(float(w), float(chart_height_)));
    for (size_t i = 0; i < chart.series.size(); ++i) {
        const Rgb c = chart.series[i].colour;
        if (i > 0) ImGui::SameLine();
        ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(c.r, c.g, c.b, 255));
        ImGui::TextUnformatted(("- " + chart.series[i].name).c_str());
        ImGui::PopStyleColor();
    }
}

}  // namespace accelviz
