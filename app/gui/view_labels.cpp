#include "app/gui/view_labels.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <imgui.h>

#include "core/render/colormap.h"
#include "core/render/views.h"

namespace accelviz {
namespace {

/// A small window over the 3D view: placed by the code, sized to its contents,
/// never focused.
constexpr ImGuiWindowFlags kViewOverlay = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                          ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoMove |
                                          ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav;
/// The same, letting clicks through to the view.
constexpr ImGuiWindowFlags kViewLabel = kViewOverlay | ImGuiWindowFlags_NoInputs;

// [SECTION] Text that fits

/// `text` cut to `width` pixels, ending in "..." where it was cut.
std::string elide(const std::string& text, float width) {
    if (ImGui::CalcTextSize(text.c_str()).x <= width) return text;
    std::string kept = text;
    while (!kept.empty()) {
        // Drop one UTF-8 character (its continuation bytes first), then any trailing spaces.
        while (!kept.empty() && (static_cast<unsigned char>(kept.back()) & 0xC0) == 0x80) kept.pop_back();
        if (!kept.empty()) kept.pop_back();
        while (!kept.empty() && kept.back() == ' ') kept.pop_back();
        if (ImGui::CalcTextSize((kept + "...").c_str()).x <= width) break;
    }
    return kept + "...";
}

/// `text` broken into lines at most `width` pixels wide, between words (at spaces
/// only: "0..11" stays whole), at most `max_lines` of them; the last ends in "..."
/// if text was left over. A word wider than a line is cut.
std::string fit_lines(const std::string& text, float width, int max_lines) {
    if (max_lines <= 0 || width <= 0) return {};
    std::vector<std::string> lines(1);
    size_t pos = 0;
    while (pos < text.size()) {
        const size_t space = std::min(text.find(' ', pos), text.size());
        const std::string word = text.substr(pos, space - pos);
        pos = space + 1;
        if (word.empty()) continue;
        const std::string joined = lines.back().empty() ? word : lines.back() + " " + word;
        if (ImGui::CalcTextSize(joined.c_str()).x <= width || lines.back().empty()) {
            lines.back() = joined;
        } else {
            if (int(lines.size()) == max_lines) {  // no line left for the rest
                lines.back() = elide(lines.back() + " " + text.substr(pos - word.size() - 1), width);
                break;
            }
            lines.push_back(word);
        }
        if (ImGui::CalcTextSize(lines.back().c_str()).x > width) lines.back() = elide(lines.back(), width);
    }
    std::string out;
    for (size_t i = 0; i < lines.size(); ++i) out += (i ? "\n" : "") + lines[i];
    return out;
}

/// A horizontal bar of the colour map over [from, to] of its range, `width` wide,
/// with tick labels under its left end, middle and right end (the middle one only
/// where it fits between the others with a gap, as in core's image legends).
void colour_bar(float width, double from, double to, const std::array<std::string, 3>* ticks) {
    const float height = 0.6f * ImGui::GetTextLineHeight();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    constexpr int kSteps = 48;
    for (int i = 0; i < kSteps; ++i) {
        const Rgb c = colormap(from + (to - from) * i / double(kSteps - 1));
        draw->AddRectFilled(ImVec2(p.x + width * i / kSteps, p.y), ImVec2(p.x + width * (i + 1) / kSteps, p.y + height),
                            IM_COL32(c.r, c.g, c.b, 255));
    }
    ImGui::Dummy(ImVec2(width, height));
    if (!ticks) return;
    const ImVec2 q = ImGui::GetCursorScreenPos();
    float w[3];
    for (int k = 0; k < 3; ++k) w[k] = ImGui::CalcTextSize((*ticks)[k].c_str()).x;
    const float gap = ImGui::GetFontSize();
    const bool middle = 2 * std::max(w[0], w[2]) + w[1] + 2 * gap <= width;
    const ImU32 text = ImGui::GetColorU32(ImGuiCol_Text);
    draw->AddText(q, text, (*ticks)[0].c_str());
    if (w[0] + w[2] + 0.5f * gap <= width) draw->AddText(ImVec2(q.x + width - w[2], q.y), text, (*ticks)[2].c_str());
    if (middle) draw->AddText(ImVec2(q.x + 0.5f * (width - w[1]), q.y), text, (*ticks)[1].c_str());
    ImGui::Dummy(ImVec2(width, ImGui::GetTextLineHeight()));
}

// [SECTION] Stacking

/// The labels of one rectangle of the view: stacked down from its top edge and up
/// from its bottom edge, in the order they are drawn, each at most as wide as the
/// rectangle. A label asks how many lines are left before it writes them.
class LabelStack {
public:
    enum class Edge { Top, Bottom };

    explicit LabelStack(const ViewRect& rect)
        : rect_(rect), margin_(0.5f * ImGui::GetFontSize()),
          top_(float(rect.y) + margin_), bottom_(float(rect.y + rect.height) - margin_) {}

    /// The width a label's contents may take.
    float content_width() const {
        return std::max(0.0f, float(rect_.width) - 2 * margin_ - 2 * ImGui::GetStyle().WindowPadding.x);
    }
    /// Lines of text that still fit between the two stacks in one more label.
    int lines_left() const {
        const float room = bottom_ - top_ - margin_ - 2 * ImGui::GetStyle().WindowPadding.y;
        return std::max(0, int(std::floor(room / ImGui::GetTextLineHeightWithSpacing())));
    }
    /// At most `wanted` lines, and at most `share` of the rectangle's height: on a
    /// small view the labels leave most of the picture visible.
    int lines_for(int wanted, float share) const {
        const int by_share = int(share * float(rect_.height) / ImGui::GetTextLineHeightWithSpacing());
        return std::min({wanted, lines_left(), std::max(1, by_share)});
    }
    /// Opens a label window at the next free place at `edge`; end() must follow.
    void begin(const char* id, Edge edge) {
        edge_ = edge;
        const bool top = edge == Edge::Top;
        ImGui::SetNextWindowPos(ImVec2(float(rect_.x) + margin_, top ? top_ : bottom_), ImGuiCond_Always,
                                ImVec2(0.0f, top ? 0.0f : 1.0f));
        ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(std::max(1.0f, float(rect_.width) - 2 * margin_), FLT_MAX));
        ImGui::SetNextWindowBgAlpha(0.75f);
        ImGui::Begin(id, nullptr, kViewLabel);
    }
    /// Closes the label, its height taken from the stack.
    void end() {
        const float used = ImGui::GetWindowSize().y + 0.5f * margin_;
        if (edge_ == Edge::Top) top_ += used;
        else bottom_ -= used;
        ImGui::End();
    }

private:
    ViewRect rect_;
    float margin_;
    float top_, bottom_;  ///< the free band between the two stacks
    Edge edge_ = Edge::Top;
};

/// A label of a title (up to two lines) and a detail paragraph in grey, cut to what fits.
void titled_label(LabelStack& stack, const char* id, LabelStack::Edge edge, const std::string& title,
                  const std::string& detail, int max_detail_lines = 4) {
    const int lines = stack.lines_for(max_detail_lines + 2, 0.3f);
    if (lines < 1) return;
    const float width = stack.content_width();
    const std::string title_fitted = fit_lines(title, width, std::min(2, lines));
    const int title_lines = int(std::count(title_fitted.begin(), title_fitted.end(), '\n')) + 1;
    const std::string detail_fitted = fit_lines(detail, width, std::min(max_detail_lines, lines - title_lines));
    stack.begin(id, edge);
    ImGui::TextUnformatted(title_fitted.c_str());
    if (!detail_fitted.empty()) ImGui::TextDisabled("%s", detail_fitted.c_str());
    stack.end();
}

// [SECTION] The labels

/// "Loading bunny.obj ... 1.2 s" at the top of the view while the worker runs, with
/// the stage's progress bar and Cancel (or Esc), and the last error message (with a
/// close button). Drawn over the labels: they must be read, and they go away (the
/// load ends, OK is clicked).
void draw_view_messages(Session& session, const ViewRect& rect, bool deterministic) {
    const float margin = ImGui::GetFontSize();
    float y = float(rect.y) + margin;
    const ImVec2 centre_top(float(rect.x) + 0.5f * float(rect.width), y);
    if (session.loader.busy()) {
        ImGui::SetNextWindowPos(centre_top, ImGuiCond_Always, ImVec2(0.5f, 0.0f));
        ImGui::SetNextWindowBgAlpha(0.85f);
        if (ImGui::Begin("##loading", nullptr, kViewOverlay)) {
            const float bar_width = 16.0f * ImGui::GetFontSize();
            if (deterministic) {
                ImGui::Text("%s ...", session.loader.activity().c_str());
                ImGui::ProgressBar(0.0f, ImVec2(bar_width, 0.0f), "");
            } else {
                // A spinner: three dots, one lit, moving with time.
                static constexpr const char* kFrames[] = {"   ", ".  ", ".. ", "..."};
                const int phase = int(ImGui::GetTime() * 4.0) % 4;
                ImGui::Text("%s%s  %.1f s", session.loader.activity().c_str(), kFrames[phase],
                            session.loader.busy_seconds());
                ImGui::ProgressBar(float(session.loader.stage_fraction()), ImVec2(bar_width, 0.0f));
            }
            ImGui::SameLine();
            if (ImGui::Button("Cancel")) session.loader.cancel();
        }
        y += ImGui::GetWindowHeight() + 0.5f * margin;
        ImGui::End();
    }
    if (!session.message.empty()) {
        ImGui::SetNextWindowPos(ImVec2(centre_top.x, y), ImGuiCond_Always, ImVec2(0.5f, 0.0f));
        ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(0.9f * float(rect.width), FLT_MAX));
        ImGui::PushStyleColor(ImGuiCol_WindowBg, session.message_is_error ? ImVec4(0.55f, 0.10f, 0.08f, 0.95f)
                                                                          : ImVec4(0.12f, 0.30f, 0.50f, 0.95f));
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 1.0f, 1.0f, 1.0f));
        if (ImGui::Begin("##message", nullptr, kViewOverlay)) {
            ImGui::PushTextWrapPos(0.85f * float(rect.width));
            ImGui::TextUnformatted(session.message.c_str());
            ImGui::PopTextWrapPos();
            if (ImGui::Button("OK")) session.message.clear();
        }
        ImGui::End();
        ImGui::PopStyleColor(2);
    }
}

/// What the overlay's colours mean (bottom of the OpenGL picture).
void draw_structure_legend(const Session& session, LabelStack& stack) {
    if (session.overlay.legend.empty() || stack.lines_left() < 2) return;
    const bool ramp = !session.overlay.boxes.empty();
    const std::string text =
        fit_lines(session.overlay.legend, stack.content_width(), stack.lines_for(4, 0.25f) - (ramp ? 1 : 0));
    stack.begin("##legend", LabelStack::Edge::Bottom);
    ImGui::TextUnformatted(text.c_str());
    // The colour ramp the overlay uses (skipping the map's darkest fifth, as it does).
    if (ramp) colour_bar(std::min(10.0f * ImGui::GetFontSize(), stack.content_width()), 0.2, 1.0, nullptr);
    stack.end();
}

/// The preset just loaded (PageDown / PageUp), for a few seconds.
void draw_preset_caption(const Session& session, LabelStack& stack) {
    if (stack.lines_left() < 1) return;
    const std::string text = fit_lines(session.presets.caption_with_text(), stack.content_width(), stack.lines_for(4, 0.3f));
    stack.begin("##preset_caption", LabelStack::Edge::Top);
    ImGui::TextUnformatted(text.c_str());
    stack.end();
}

/// Split view, left half: which rasterizer drew it and the work it did.
void draw_raster_label(const AppState& state, const Session& session, LabelStack& stack, bool deterministic) {
    char text[256];
    const auto& shown_cast = session.ray_cast.shown();
    if (session.ray_cast.fill_shown()) {
        const RasterFillCounts& c = session.ray_cast.raster_fill_shown();
        std::snprintf(text, sizeof text, "%llu of %llu triangles: %llu depth tests, %llu writes, %llu of them overwrites",
                      (unsigned long long)c.triangles, (unsigned long long)c.triangle_count,
                      (unsigned long long)c.depth_tests, (unsigned long long)c.depth_writes,
                      (unsigned long long)c.overwrites);
        titled_label(stack, "##raster_label", LabelStack::Edge::Top, "Rasterization: for each triangle (CPU z-buffer)",
                     text);
    } else if (state.view.fill_order && session.scene &&
               session.scene->mesh->triangle_count() > kFillOrderMaxTriangles) {
        std::snprintf(text, sizeof text, "the fill order replays scenes of up to %llu triangles; this one has %zu",
                      (unsigned long long)kFillOrderMaxTriangles, session.scene->mesh->triangle_count());
        titled_label(stack, "##raster_label", LabelStack::Edge::Top, "Fill order: too many triangles", text);
    } else if (session.ray_cast.left_texture() != nullptr) {
        const RasterStats& r = shown_cast->raster_work;
        std::snprintf(text, sizeof text,
                      "%llu triangles rasterized, %llu pixel centres tested, %llu fragments, %llu depth writes",
                      (unsigned long long)r.triangles_rasterized, (unsigned long long)r.pixels_tested,
                      (unsigned long long)r.fragments, (unsigned long long)r.depth_writes);
        std::string detail = text;
        if (state.view.left_view == LeftView::RasterDepth) {
            std::snprintf(text, sizeof text, "; grey: t %.3g (light) .. %.3g (dark), same scale as the ray cast's",
                          shown_cast->t_near, shown_cast->t_far);
            detail += text;
        }
        if (!deterministic) {
            std::snprintf(text, sizeof text, "  (%.0f ms)", shown_cast->raster_milliseconds);
            detail += text;
        }
        titled_label(stack, "##raster_label", LabelStack::Edge::Top,
                     state.view.left_view == LeftView::RasterDepth ? "Rasterized depth (CPU z-buffer, core)"
                                                                   : "Rasterized (CPU z-buffer, core)",
                     detail);
    } else if (state.view.left_view == LeftView::OpenGlDepth) {
        std::string detail = "the depth buffer read back, as the distance t along each pixel's ray";
        if (shown_cast && shown_cast->t_far > shown_cast->t_near) {
            std::snprintf(text, sizeof text, "; grey: t %.3g (light) .. %.3g (dark), same scale as the ray cast's",
                          shown_cast->t_near, shown_cast->t_far);
            detail += text;
        }
        titled_label(stack, "##raster_label", LabelStack::Edge::Top, "Rasterized depth (OpenGL z-buffer)", detail);
    } else {
        const size_t triangles = session.scene ? session.scene->mesh->triangle_count() : 0;
        std::snprintf(text, sizeof text, "every triangle projected and filled: %zu triangles", triangles);
        titled_label(stack, "##raster_label", LabelStack::Edge::Top, "Rasterized (OpenGL z-buffer)", text);
    }
}

/// Split view, right half, bottom: the colour scale of a heat map or of the depth
/// difference (what core's image legends show, in the window's font).
void draw_ray_legend(const AppState& state, const Session& session, LabelStack& stack) {
    const RightView right = state.view.right_view;
    if (stack.lines_left() < 3) return;
    std::string title;
    std::array<std::string, 3> ticks;
    const bool gpu = session.gpu_cast_shown && session.gpu_cast.shown();
    if (gpu && (is_heat(right) || right == RightView::HeatStack)) {
        const HeatScale& scale = session.gpu_cast.heat_scale_shown();
        char text[96];
        std::snprintf(text, sizeof text, "%s per invocation (mean %.1f)",
                      right == RightView::HeatNodes  ? "loop iterations"
                      : right == RightView::HeatTris ? "triangle tests"
                                                     : "deepest stack",
                      scale.mean);
        title = text;
        ticks = scale.ticks;
    } else if (gpu || !session.ray_cast.shown() || session.ray_cast.fill_shown()) {
        return;
    } else if (is_heat(right)) {
        const HeatScale& scale = session.ray_cast.heat_scale_shown();
        char text[96];
        std::snprintf(text, sizeof text, "%s per pixel (mean %.1f)",
                      right == RightView::HeatNodes ? "nodes" : "triangle tests", scale.mean);
        title = text;
        ticks = scale.ticks;
    } else if (right == RightView::DepthDiff) {
        title = "relative depth error (log scale)";
        ticks = depth_diff_ticks();
    } else {
        return;
    }
    const float width = std::min(16.0f * ImGui::GetFontSize(), stack.content_width());
    const std::string title_fitted = fit_lines(title, width, stack.lines_left() >= 4 ? 2 : 1);
    stack.begin("##ray_legend", LabelStack::Edge::Bottom);
    ImGui::TextUnformatted(title_fitted.c_str());
    colour_bar(width, 0.0, 1.0, &ticks);
    stack.end();
}

/// Split view, right half, top: the ray caster's structure, what the picture
/// shows, and the work per ray.
/// The right half cast by the GPU: what it shows, its invocations and time, and how
/// far it agrees with the CPU's cast of the same camera (when that one is there).
void draw_gpu_label(const AppState& state, const Session& session, LabelStack& stack, bool deterministic) {
    const RightView right = state.view.right_view;
    std::string title = "Ray cast (GPU compute shader, bvh)";
    if (right == RightView::HeatNodes) title += ": loop iterations (nodes visited) per invocation";
    if (right == RightView::HeatTris) title += ": triangle tests per invocation";
    if (right == RightView::HeatStack) title += ": deepest stack per invocation";
    const GpuCast& gpu = *session.gpu_cast.shown();
    char text[320];
    std::snprintf(text, sizeof text, "%d x %d invocations, one per pixel, each with its own stack (algorithm 2)",
                  gpu.width, gpu.height);
    std::string detail = text;
    if (const auto& cpu = session.ray_cast.shown();
        cpu && cpu->frame.width == gpu.width && cpu->frame.height == gpu.height && state.camera &&
        cpu->key.camera == *state.camera && !session.gpu_cast.stale()) {
        const GpuAgreement a = compare_with_cpu(gpu, cpu->frame.tri, cpu->frame.depth);
        std::snprintf(text, sizeof text, "; the same triangle as the CPU on %.4f%% of pixels, t within %.2g",
                      100.0 * a.same_share(), a.max_relative_t);
        detail += text;
    }
    if (is_heat(right) || right == RightView::HeatStack) {
        std::snprintf(text, sizeof text, "; mean %.2f per pixel", session.gpu_cast.heat_scale_shown().mean);
        detail += text;
    }
    if (!deterministic) {
        std::snprintf(text, sizeof text, "  (%.0f ms, %s)", gpu.gpu_ms, session.gpu_cast.device().c_str());
        detail += text;
    }
    if (session.gpu_cast.stale()) detail += "  waiting for the camera to stop ...";
    titled_label(stack, "##ray_label", LabelStack::Edge::Top, title, detail, 4);
}

void draw_ray_label(const AppState& state, const Session& session, LabelStack& stack, bool deterministic) {
    if (session.gpu_cast_shown && session.gpu_cast.shown()) return draw_gpu_label(state, session, stack, deterministic);
    char text[256];
    const RightView right = state.view.right_view;
    const size_t triangles = session.scene ? session.scene->mesh->triangle_count() : 0;
    const std::string structure = session.scene ? std::string(to_string(session.scene->accel_config.type)) : "?";
    std::string title = "Ray cast (CPU, " + structure + ")";
    if (right == RightView::HeatNodes) title += ": nodes visited per pixel";
    if (right == RightView::HeatTris) title += ": triangle tests per pixel";
    if (is_heat(right) && session.ray_cast.heat_rays_shown() != HeatRays::Primary)
        title += std::string(" by ") + std::string(to_string(session.ray_cast.heat_rays_shown())) + " rays";
    if (right == RightView::Depth) title += ": depth";
    if (right == RightView::DepthDiff) title = "Depth: CPU raster vs ray cast (" + structure + ")";
    if (right == RightView::HeatStack) title += " (the stack depth is the GPU's: View, Ray cast by GPU)";
    if (!session.gpu_cast_reason.empty()) title += " (not the GPU: " + session.gpu_cast_reason + ")";
    if (session.ray_cast.fill_shown()) {
        const RayFillCounts& c = session.ray_cast.ray_fill_shown();
        std::snprintf(text, sizeof text, "%llu of %llu pixels, one ray each: %llu nodes, %llu triangle tests",
                      (unsigned long long)c.pixels, (unsigned long long)c.pixel_count, (unsigned long long)c.nodes,
                      (unsigned long long)c.triangle_tests);
        titled_label(stack, "##ray_label", LabelStack::Edge::Top, "Ray casting: for each pixel (CPU, " + structure + ")",
                     text);
        return;
    }
    std::string detail = "computing ...";
    if (const auto& shown = session.ray_cast.shown()) {
        const Counters& w = shown->frame.work;
        const double rays = double(shown->key.width) * shown->key.height;
        detail.clear();
        if (right == RightView::DepthDiff) {
            const DepthAgreement& a = session.ray_cast.depth_agreement_shown();
            std::snprintf(text, sizeof text,
                          "grey: agree within 1e-04 relative (%.3f%% of shared pixels); magenta: raster only, "
                          "cyan: ray cast only (%.3f%% of pixels); ",
                          a.agreeing_percent(), a.coverage_differs_percent());
            detail = text;
        }
        std::snprintf(text, sizeof text,
                      "%.0f rays x (%.1f nodes, %.1f box tests, %.1f triangle tests) (naive: %zu triangle tests per ray)",
                      rays, w.nodes_visited / rays, w.box_tests / rays, w.triangle_tests / rays, triangles);
        detail += text;
        // The secondary rays of the point light (the any-hit query stops at the first occluder).
        for (const auto& [kind, work] : {std::pair{"shadow", &shown->frame.shadow}, std::pair{"reflection", &shown->frame.reflection}})
            if (work->rays > 0) {
                const double n = double(work->rays);
                std::snprintf(text, sizeof text, "; + %llu %s rays x (%.1f nodes, %.1f triangle tests)",
                              (unsigned long long)work->rays, kind, double(work->work.nodes_visited) / n,
                              double(work->work.triangle_tests) / n);
                detail += text;
            }
        if (right == RightView::Depth) {
            std::snprintf(text, sizeof text, "; grey: t %.3g (light) .. %.3g (dark)", shown->t_near, shown->t_far);
            detail += text;
        }
        if (is_heat(right) && state.view.heat_same_scale)
            detail += "; heat scale shared by all structures (largest since the scene loaded)";
        if (!deterministic) {
            std::snprintf(text, sizeof text, "  (%.0f ms)", shown->milliseconds);
            detail += text;
        }
        if (session.ray_cast.stale()) detail += "  updating ...";
    }
    titled_label(stack, "##ray_label", LabelStack::Edge::Top, title, detail, right == RightView::DepthDiff ? 6 : 4);
}

/// The point light as a small sun (a disc and eight rays, dark-edged to read on any
/// background) with "light" beside it, where the camera sees it; nothing when it is
/// behind the camera or outside the view.
void draw_light_marker(const AppState& state, Session& session, const ViewRect& rect) {
    if (!state.light.point_light() || !session.scene || !state.camera || rect.empty()) return;
    const Camera camera(*state.camera, rect.width, rect.height);
    const Camera::ImagePoint at = camera.project(light_position(state.light, session.scene->bounds));
    if (!(at.depth > 0) || at.x < 0 || at.y < 0 || at.x > rect.width || at.y > rect.height) return;
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    const ImVec2 c(float(rect.x + at.x), float(rect.y + at.y));
    session.light_markers.push_back({c.x, c.y});
    const float r = float(light_marker_radius(state.view.ui_scale));
    const ImU32 sun = IM_COL32(255, 214, 64, 255), edge = IM_COL32(0, 0, 0, 220);
    for (int k = 0; k < 8; ++k) {
        const float a = float(k) * 0.785398163f;
        const ImVec2 from(c.x + 0.55f * r * std::cos(a), c.y + 0.55f * r * std::sin(a));
        const ImVec2 to(c.x + r * std::cos(a), c.y + r * std::sin(a));
        draw->AddLine(from, to, edge, 4.0f * state.view.ui_scale);
        draw->AddLine(from, to, sun, 2.0f * state.view.ui_scale);
    }
    draw->AddCircleFilled(c, 0.45f * r, sun);
    draw->AddCircle(c, 0.45f * r, edge, 0, 1.5f * state.view.ui_scale);
    const ImVec2 text(c.x + r + 4.0f, c.y - ImGui::GetFontSize() * 0.5f);
    draw->AddText(ImVec2(text.x + 1, text.y + 1), edge, "light");
    draw->AddText(text, sun, "light");
}

/// The nearest-point query point q as a ring (white, dark-edged) to grab and drag;
/// nothing when it is behind the camera or outside the view.
void draw_query_marker(const AppState& state, Session& session, const ViewRect& rect) {
    if (!state.nearest.open || !state.nearest.point || !state.camera || rect.empty()) return;
    const Camera camera(*state.camera, rect.width, rect.height);
    const Camera::ImagePoint at = camera.project(*state.nearest.point);
    if (!(at.depth > 0) || at.x < 0 || at.y < 0 || at.x > rect.width || at.y > rect.height) return;
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    const ImVec2 c(float(rect.x + at.x), float(rect.y + at.y));
    session.query_markers.push_back({c.x, c.y});
    const float r = 0.6f * float(light_marker_radius(state.view.ui_scale));
    draw->AddCircle(c, r, IM_COL32(0, 0, 0, 220), 0, 4.0f * state.view.ui_scale);
    draw->AddCircle(c, r, IM_COL32(255, 255, 255, 255), 0, 2.0f * state.view.ui_scale);
}

}  // namespace

void draw_view_labels(const AppState& state, Session& session, const ViewAreas& areas, bool structure_legend,
                      bool deterministic) {
    draw_view_messages(session, areas.view, deterministic);
    session.light_markers.clear();
    draw_light_marker(state, session, areas.gl_view);
    if (areas.split) draw_light_marker(state, session, areas.ray_view);
    session.query_markers.clear();
    draw_query_marker(state, session, areas.gl_view);
    // The bottom stacks first (legends keep their size); the top labels wrap into the rest.
    LabelStack gl(areas.gl_view);
    if (structure_legend) draw_structure_legend(session, gl);
    if (areas.split) {
        LabelStack ray(areas.ray_view);
        draw_ray_legend(state, session, ray);
        draw_raster_label(state, session, gl, deterministic);
        draw_ray_label(state, session, ray, deterministic);
        // The divider between the halves.
        const float x = float(areas.ray_view.x) - 1.0f;
        ImGui::GetBackgroundDrawList()->AddLine(ImVec2(x, float(areas.view.y)),
                                                ImVec2(x, float(areas.view.y + areas.view.height)),
                                                IM_COL32(255, 255, 255, 255), 2.0f);
    }
    // A deterministic frame (headless, golden images) does not read the clock: it
    // shows the caption of the preset it was given, as the window does on loading it.
    if (deterministic ? session.presets.current() >= 0 : session.presets.caption_fresh())
        draw_preset_caption(session, gl);
}

}  // namespace accelviz
