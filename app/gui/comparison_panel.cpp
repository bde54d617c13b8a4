#include "app/gui/comparison_panel.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include <imgui.h>

#include "app/gui/panel_widgets.h"

namespace accelviz {

namespace {

constexpr ImU32 kPlotBg = IM_COL32(28, 30, 36, 255);
constexpr ImU32 kPlotFrame = IM_COL32(110, 110, 120, 255);
constexpr ImU32 kGridLine = IM_COL32(60, 62, 70, 255);
constexpr ImU32 kFrameLine = IM_COL32(200, 200, 205, 255);
/// One colour per row of comparison_structures(): naive, grid, KD tree, octree, BVH.
constexpr ImU32 kRowColours[] = {IM_COL32(170, 170, 175, 255), IM_COL32(245, 160, 60, 255),
                                 IM_COL32(110, 210, 110, 255), IM_COL32(200, 130, 235, 255),
                                 IM_COL32(80, 200, 245, 255)};
ImU32 row_colour(size_t i) { return kRowColours[i % std::size(kRowColours)]; }

/// A count for a projector: 940, 3.1k, 2.4M, 1.1G.
std::string count_text(double n) {
    if (n < 1e3) return text_of("%.0f", n);
    if (n < 1e6) return text_of(n < 1e4 ? "%.1fk" : "%.0fk", n / 1e3);
    if (n < 1e9) return text_of(n < 1e7 ? "%.1fM" : "%.0fM", n / 1e6);
    if (n < 1e12) return text_of("%.1fG", n / 1e9);
    return text_of("%.1e", n);
}

std::string bytes_text(double bytes) {
    if (bytes <= 0) return "-";
    if (bytes < 1e6) return text_of("%.0f kB", bytes / 1e3);
    if (bytes < 1e9) return text_of(bytes < 1e7 ? "%.1f MB" : "%.0f MB", bytes / 1e6);
    return text_of("%.1f GB", bytes / 1e9);
}

std::string ms_text(double ms) {
    if (ms < 10) return text_of("%.2f ms", ms);
    if (ms < 1e4) return text_of("%.0f ms", ms);
    return text_of("%.0f s", ms / 1e3);
}

/// The chart's ray axis: 1 to a power of ten past 10 frames and past every break-even,
/// at most 10^9 (a break-even beyond is "never" in practice; the table gives it).
double chart_max_rays(const StructureComparison& c) {
    double most = 10.0 * double(c.width) * double(c.height);
    for (size_t i = 1; i < c.rows.size(); ++i)
        if (auto rays = break_even_rays(c.rows[0], c.rows[i])) most = std::max(most, 10.0 * *rays);
    return std::pow(10.0, std::clamp(std::ceil(std::log10(std::max(most, 10.0))), 1.0, 9.0));
}

}  // namespace

ComparisonPanel::~ComparisonPanel() {
    if (progress_) progress_->cancel();
}

void ComparisonPanel::start(const Key& key, std::shared_ptr<const LoadedScene> scene) {
    if (progress_) progress_->cancel();  // an older measurement still running is not wanted
    requested_mesh_ = scene->mesh;
    requested_file_ = scene->structure_file;
    MeasureOptions with_file = options;
    if (scene->structure_file && scene->structure_file->check.valid()) {
        // The student's tree beside ours: its "build" is reading and checking the file.
        AccelConfig file_config = scene->accel_config;
        with_file.extra_structures.push_back({"file's tree", file_config});
    }
    error_.clear();
    progress_ = std::make_shared<WorkProgress>();
    row_ = std::make_shared<std::atomic<int>>(0);
    job_.submit([key, scene = std::move(scene), progress = progress_, row = row_, options = with_file]() mutable {
        Result result{key, scene, std::nullopt, ""};
        options.progress = progress.get();
        options.current_row = row.get();
        auto measured = measure_structures(*scene->mesh, Camera(key.camera, key.width, key.height), options);
        if (measured) result.comparison = std::move(*measured);
        else result.error = measured.error();
        return result;
    });
}

void ComparisonPanel::cancel() {
    if (job_.busy() && progress_) {
        progress_->cancel();
        requested_mesh_.reset();  // not measured: the next showing measures again
    }
}

void ComparisonPanel::take_finished() {
    auto done = job_.take();
    if (!done) return;
    if (done->comparison) result_ = std::move(*done);
    else if (done->error != WorkProgress::cancelled_error().message) error_ = done->error;
}

void ComparisonPanel::update(const AppState& state, const std::shared_ptr<const LoadedScene>& scene, int view_width,
                             int view_height, bool shown, bool wait) {
    if (!shown || !scene || !state.camera || view_width <= 0 || view_height <= 0) {
        cancel();  // a measurement nobody sees is not wanted
        take_finished();
        return;
    }
    const Key key{scene->mesh.get(), *state.camera, view_width, view_height};
    shown_view_ = key;
    // A new mesh is measured at once; a moved camera or a resized view when asked (a
    // measurement builds every structure: not on every drag).
    if (requested_mesh_.lock() != scene->mesh || requested_file_.lock() != scene->structure_file || measure_again_) {
        measure_again_ = false;
        start(key, scene);
    }
    if (wait) job_.wait();
    take_finished();
}

void ComparisonPanel::draw(float width, bool lecture) {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextUnformatted("Structures compared: measured here, now");
    if (job_.busy()) {
        const auto structures = comparison_structures();
        const int row = std::clamp(row_ ? row_->load() : 0, 0, int(structures.size()) - 1);
        ImGui::Text("Measuring %s (%d of %zu) ...", structures[size_t(row)].first.c_str(), row + 1, structures.size());
        progress_with_cancel(progress_.get(), width);
    }
    if (!error_.empty() && !job_.busy()) error_line("Could not measure", error_);
    const StructureComparison* c = measured();
    if (!c) {
        if (!job_.busy() && ImGui::Button("Measure")) measure_again_ = true;
        ImGui::PopTextWrapPos();
        return;
    }
    ImGui::TextDisabled("One thread; %s triangles; %s rays from a %d x %d view.", count_text(double(c->triangles)).c_str(),
                        count_text(double(c->sample_rays)).c_str(), c->width, c->height);
    const bool moved = !(shown_view_ == result_->key);
    if (!job_.busy()) {
        if (ImGui::Button("Measure again")) measure_again_ = true;
        if (moved) {
            ImGui::SameLine();
            ImGui::TextDisabled("(the view has changed since)");
        }
    }
    draw_table(*c, lecture);
    ImGui::Spacing();
    draw_chart(*c, width, lecture);
    ImGui::PopTextWrapPos();
}

void ComparisonPanel::draw_table(const StructureComparison& c, bool lecture) const {
    constexpr ImGuiTableFlags kFlags =
        ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp | ImGuiTableFlags_BordersInnerV;
    ImGui::PushTextWrapPos(-1.0f);  // a cell's figure on one line
    if (!ImGui::BeginTable("comparison", 8, kFlags)) {
        ImGui::PopTextWrapPos();
        return;
    }
    for (const char* heading : {"", "build", "memory", "Mrays/s", "nodes", "tests", "again", "pays off"})
        ImGui::TableSetupColumn(heading);
    ImGui::TableHeadersRow();
    auto right_aligned = [](const std::string& text) {
        ImGui::TableNextColumn();
        const float room = ImGui::GetContentRegionAvail().x - ImGui::CalcTextSize(text.c_str()).x;
        if (room > 0) ImGui::SetCursorPosX(ImGui::GetCursorPosX() + room);
        ImGui::TextUnformatted(text.c_str());
    };
    for (size_t i = 0; i < c.rows.size(); ++i) {
        const StructureMeasurement& row = c.rows[i];
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::PushStyleColor(ImGuiCol_Text, row_colour(i));
        ImGui::TextUnformatted(row.label.c_str());
        ImGui::PopStyleColor();
        right_aligned(row.type == AccelType::Naive ? "-" : ms_text(row.build_ms));
        right_aligned(bytes_text(double(row.memory_bytes)));
        right_aligned(text_of(row.mrays_per_second() < 1 ? "%.2g" : "%.1f", row.mrays_per_second()));
        right_aligned(text_of("%.1f", row.nodes_per_ray));
        right_aligned(text_of(row.triangle_tests_per_ray < 1e4 ? "%.1f" : "%.0f", row.triangle_tests_per_ray));
        right_aligned(text_of("%.2f", row.repeats_per_ray));
        if (i == 0) {
            right_aligned("-");
        } else {
            const auto rays = break_even_rays(c.rows[0], row);
            right_aligned(rays ? count_text(*rays) + " rays" : "never");
        }
    }
    ImGui::EndTable();
    ImGui::PopTextWrapPos();
    if (!lecture)
        ImGui::TextDisabled("Per ray: nodes (or cells) visited, triangle tests, and a triangle met again (tested "
                            "again or skipped by the mailbox). Pays off: the rays after which build + rays costs "
                            "less than naive.");
    uint64_t mismatches = 0;
    for (const StructureMeasurement& row : c.rows) mismatches += row.mismatches;
    if (mismatches == 0)
        ImGui::TextDisabled("Every structure found naive's closest hit for each of the %s rays naive traced.",
                            count_text(double(c.rows.empty() ? 0 : c.rows[0].rays)).c_str());
    else {
        ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(255, 120, 100, 255));
        ImGui::Text("%llu closest hits differ from naive's.", (unsigned long long)mismatches);
        ImGui::PopStyleColor();
    }
}

void ComparisonPanel::draw_chart(const StructureComparison& c, float width, bool lecture) const {
    const AmortizationChart chart = amortization_chart(c, chart_max_rays(c));
    if (chart.series.empty()) return;
    ImGui::TextUnformatted("Build + rays x time per ray, against rays (log-log)");
    const float font = ImGui::GetFontSize();
    const float line = std::max(2.0f, 0.125f * font);
    const float label_w = ImGui::CalcTextSize("10000 s").x + 0.4f * font;
    // As tall as the panel allows under the legend and the two lines below it (lecture
    // mode's big text leaves less), but never flat.
    const float below = (lecture ? 4.5f : 6.0f) * font;
    const float plot_h = std::max(5.0f * font, std::min(0.6f * width, ImGui::GetContentRegionAvail().y - below));
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const ImVec2 p0(origin.x + label_w, origin.y + 0.3f * font), p1(origin.x + width - 0.5f * font, p0.y + plot_h);
    ImGui::Dummy(ImVec2(width, plot_h + 1.6f * ImGui::GetTextLineHeight()));
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImU32 label_colour = ImGui::GetColorU32(ImGuiCol_Text);
    draw->AddRectFilled(p0, p1, kPlotBg);

    // Log axes: rays 1 .. max, total time over the decades the series span.
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    for (const auto& s : chart.series)
        for (double ms : s.total_ms)
            if (ms > 0) lo = std::min(lo, ms), hi = std::max(hi, ms);
    if (!(hi > 0)) return;
    const double y_lo = std::floor(std::log10(lo)), y_hi = std::max(y_lo + 1, std::ceil(std::log10(hi)));
    const double x_hi = std::log10(chart.max_rays);
    auto x_of = [&](double rays) { return p0.x + float(std::log10(std::max(rays, 1.0)) / x_hi) * (p1.x - p0.x); };
    auto y_of = [&](double ms) {
        const double l = std::clamp(std::log10(std::max(ms, 1e-300)), y_lo, y_hi);
        return p1.y - float((l - y_lo) / (y_hi - y_lo)) * (p1.y - p0.y);
    };
    // Decade lines, labelled every k-th decade so that the labels do not crowd.
    const float x_label_w = ImGui::CalcTextSize("100M").x + 0.8f * font;
    // (decades / k + 1 labels must fit: k >= decades * label / (length - label).)
    auto label_step = [](double decades, float label, float length) {
        return std::max(1, int(std::ceil(decades * label / std::max(1.0f, length - label))));
    };
    const int x_step = label_step(x_hi, x_label_w, p1.x - p0.x);
    const int y_step = label_step(y_hi - y_lo, 1.1f * ImGui::GetTextLineHeight(), p1.y - p0.y);
    for (int d = 0; d <= int(x_hi); ++d) {
        const float x = x_of(std::pow(10.0, d));
        draw->AddLine(ImVec2(x, p0.y), ImVec2(x, p1.y), kGridLine);
        if (d % x_step) continue;
        const std::string text = count_text(std::pow(10.0, d));
        const float w = ImGui::CalcTextSize(text.c_str()).x;
        draw->AddText(ImVec2(std::clamp(x - 0.5f * w, p0.x, p1.x - w), p1.y + 0.1f * font), label_colour, text.c_str());
    }
    for (int d = int(y_lo); d <= int(y_hi); ++d) {
        const float y = y_of(std::pow(10.0, d));
        draw->AddLine(ImVec2(p0.x, y), ImVec2(p1.x, y), kGridLine);
        if ((d - int(y_lo)) % y_step) continue;
        const std::string text = ms_text(std::pow(10.0, d));
        const float h = ImGui::GetTextLineHeight();
        draw->AddText(ImVec2(origin.x, std::clamp(y - 0.5f * h, p0.y, p1.y - h)), label_colour, text.c_str());
    }
    // One frame of this view: the rays a picture needs.
    const double frame_rays = double(c.width) * double(c.height);
    const float frame_x = x_of(frame_rays);
    draw->AddLine(ImVec2(frame_x, p0.y), ImVec2(frame_x, p1.y), kFrameLine, 1.0f);
    draw->AddText(ImVec2(frame_x + 3.0f, p0.y), kFrameLine, "one frame");
    // The series, clipped to the plot.
    draw->PushClipRect(p0, p1, true);
    for (size_t s = 0; s < chart.series.size(); ++s) {
        const auto& series = chart.series[s];
        for (size_t i = 1; i < series.rays.size(); ++i)
            draw->AddLine(ImVec2(x_of(series.rays[i - 1]), y_of(series.total_ms[i - 1])),
                          ImVec2(x_of(series.rays[i]), y_of(series.total_ms[i])), row_colour(s), line);
    }
    // Break-even points: where a structure's line crosses naive's.
    // Labels alternate above and below in order of rays, so that close points stay readable.
    std::vector<AmortizationChart::BreakEven> points = chart.break_even;
    std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return a.rays < b.rays; });
    for (size_t k = 0; k < points.size(); ++k) {
        const auto& point = points[k];
        const ImVec2 p(x_of(point.rays), y_of(point.total_ms));
        draw->AddCircleFilled(p, 0.3f * font, row_colour(point.row));
        draw->AddCircle(p, 0.3f * font, IM_COL32(255, 255, 255, 255), 0, 1.5f);
        const float dy = k % 2 ? 0.2f * font : -1.2f * font;
        draw->AddText(ImVec2(p.x + 0.4f * font, p.y + dy), row_colour(point.row), count_text(point.rays).c_str());
    }
    draw->PopClipRect();
    draw->AddRect(p0, p1, kPlotFrame);
    // Legend: the structures in their colours, then what the dots say.
    ImGui::SetCursorScreenPos(ImVec2(p0.x, p1.y + 1.3f * ImGui::GetTextLineHeight()));
    for (size_t s = 0; s < chart.series.size(); ++s) {
        if (s > 0) ImGui::SameLine();
        ImGui::PushStyleColor(ImGuiCol_Text, row_colour(s));
        ImGui::TextUnformatted(chart.series[s].label.c_str());
        ImGui::PopStyleColor();
    }
    if (!lecture)
        ImGui::TextDisabled("Dots: the rays after which a structure has paid for its build (its line crosses naive's).");
    // The lecture's sentence, for the last row (the BVH).
    const size_t last = c.rows.size() - 1;
    if (last > 0)
        if (const auto rays = break_even_rays(c.rows[0], c.rows[last]))
            ImGui::Text("After %s rays the %s has paid for itself; one frame of this view is %s rays.",
                        count_text(*rays).c_str(), c.rows[last].label.c_str(), count_text(frame_rays).c_str());
}

}  // namespace accelviz
