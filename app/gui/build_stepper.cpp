#include "app/gui/build_stepper.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <span>
#include <tuple>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key codes only: ImGui 1.86 indexes io.KeysDown by the GLFW backend's codes
#include <imgui.h>

#include "app/gui/camera_control.h"
#include "app/gui/panel_widgets.h"
#include "app/gui/structure_overlay.h"
#include "core/accel/accelerator.h"
#include "core/accel/factory.h"
#include "core/accel/kd_sah.h"
#include "core/accel/kd_tree.h"
#include "core/accel/sah.h"
#include "core/accel/wide_bvh.h"

namespace accelviz {

namespace {

// [SECTION] Colours: the same in the chart, its legend and the 3D view

/// The node's box: white on a dark background, near-black on a light one.
Rgba8 node_box_colour(Rgb background) {
    const int luma = (299 * background.r + 587 * background.g + 114 * background.b) / 1000;
    return luma > 128 ? Rgba8{20, 20, 24, 255} : Rgba8{255, 255, 255, 255};
}
constexpr Rgba8 kLeftColour{255, 150, 40, 255};   ///< left child: box, triangles, chart side
constexpr Rgba8 kRightColour{70, 160, 255, 255};  ///< right child
constexpr Rgb kLeafTriangles{240, 210, 80};
constexpr Rgb kDimMesh{92, 92, 98};
constexpr Rgba8 kPlaneColour{80, 225, 110, 80};   ///< the split plane (the chart's green)

ImU32 im(Rgba8 c) { return IM_COL32(c.r, c.g, c.b, c.a); }
constexpr ImU32 kPlotBg = IM_COL32(28, 30, 36, 255);
constexpr ImU32 kPlotFrame = IM_COL32(110, 110, 120, 255);
constexpr ImU32 kCurve = IM_COL32(235, 235, 235, 255);
constexpr ImU32 kEmpty = IM_COL32(140, 140, 150, 255);
constexpr ImU32 kBest = IM_COL32(80, 225, 110, 255);
constexpr ImU32 kLeafLine = IM_COL32(255, 90, 70, 255);
constexpr ImU32 kMedian = IM_COL32(235, 110, 235, 255);
constexpr ImU32 kMidpoint = IM_COL32(90, 215, 235, 255);
constexpr ImU32 kAxisText = IM_COL32(220, 220, 225, 255);

const char* kAxisNames[3] = {"x", "y", "z"};

/// A cost for a label: whole numbers from 1000 on (no exponents on a projector).
std::string cost_text(double cost) {
    return std::abs(cost) >= 1000.0 ? text_of("%.0f", cost) : text_of("%.4g", cost);
}

bool is_sah(BvhBuilder b) { return b == BvhBuilder::SahBinned || b == BvhBuilder::SahSweep; }

/// A coloured square in the text flow (legend keys).
void swatch(ImU32 colour) {
    const float size = ImGui::GetTextLineHeight() * 0.8f;
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const float dy = (ImGui::GetTextLineHeight() - size) * 0.5f;
    ImGui::GetWindowDrawList()->AddRectFilled(ImVec2(p.x, p.y + dy), ImVec2(p.x + size, p.y + dy + size), colour);
    ImGui::Dummy(ImVec2(size, ImGui::GetTextLineHeight()));
    ImGui::SameLine();
}

/// Left/Right step, Home/End jump over steps 0..last (the active stepper owns the arrows).
void step_keys(int& step, int last) {
    if (ImGui::IsKeyPressed(GLFW_KEY_RIGHT, true)) step = std::min(step + 1, last);
    if (ImGui::IsKeyPressed(GLFW_KEY_LEFT, true)) step = std::max(step - 1, 0);
    if (ImGui::IsKeyPressed(GLFW_KEY_HOME, false)) step = 0;
    if (ImGui::IsKeyPressed(GLFW_KEY_END, false)) step = last;
}

/// The timeline's buttons |< < > >| and "next split" (to the next step `is_split` says
/// is a split, leaves skipped), each followed on the same line.
template <class IsSplit>
void timeline_buttons(int& step, int last, IsSplit&& is_split) {
    if (ImGui::Button("|<")) step = 0;
    ImGui::SameLine();
    if (ImGui::Button("<")) step = std::max(0, step - 1);
    ImGui::SameLine();
    if (ImGui::Button(">")) step = std::min(last, step + 1);
    ImGui::SameLine();
    if (ImGui::Button(">|")) step = last;
    ImGui::SameLine();
    if (ImGui::Button("next split")) {
        for (int k = step + 1; k <= last; ++k)
            if (is_split(k)) {
                step = k;
                break;
            }
    }
    ImGui::SameLine();
}

/// The sidebar's switch for a stepper, with the keys' hint when on and what it shows when off.
void stepper_switch(const char* label, bool& active, const char* shows) {
    ImGui::Checkbox(label, &active);
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    ImGui::TextWrapped("%s", active ? "Left/Right step, Home/End jump (the camera: mouse)." : shows);
    ImGui::PopStyleColor();
}

/// The triangles `ids` of `mesh` as a mesh of their own (the same vertices), to draw in a colour.
Mesh mesh_subset(const Mesh& mesh, std::span<const uint32_t> ids) {
    Mesh part;
    part.positions = mesh.positions;
    part.indices.reserve(ids.size());
    for (uint32_t t : ids) part.indices.push_back(mesh.indices[t]);
    return part;
}

/// A node's box a little larger than it is: its edges would otherwise lie on its
/// children's and be hidden by them.
BoxInstance node_box(const Aabb& box, Rgba8 colour) {
    const Vec3 grow = box.extent() * 0.015f;
    return {box.lo - grow, box.hi + grow, colour};
}

/// A split plane across a node's box, translucent.
ColouredQuad split_plane_quad(const Aabb& box, int axis, float position) {
    ColouredQuad quad;
    const std::array<Vec3, 4> corners = plane_across_box(box, axis, position);
    std::copy(corners.begin(), corners.end(), quad.corners);
    quad.colour = kPlaneColour;
    return quad;
}

}  // namespace

// [SECTION] Recording

BvhConfig chart_config(const BvhConfig& built, const BuildStepSettings& settings) {
    BvhConfig c = built;
    if (settings.bins) c.bins = std::clamp(*settings.bins, kBvhMinBins, kBvhMaxBins);
    if (settings.cost_trav) c.cost_trav = std::max(0.0f, *settings.cost_trav);
    if (settings.cost_isect && *settings.cost_isect > 0.0f) c.cost_isect = *settings.cost_isect;
    return c;
}

std::shared_ptr<const BuildTrace> record_build(std::shared_ptr<const LoadedScene> scene) {
    if (!scene || !scene->accel || !scene->mesh) return nullptr;
    const std::optional<BvhConfig> config = binary_bvh_config(*scene->accel);
    if (!config) return nullptr;
    auto trace = std::make_shared<BuildTrace>();
    trace->config = *config;
    trace->scene_width = structure_if<WideBvh<4>>(*scene->accel)   ? 4
                         : structure_if<WideBvh<8>>(*scene->accel) ? 8
                                                                   : 2;
    BuildRecorder recorder;
    recorder.record_candidates = false;  // the chart recomputes one node's (sah_chart.h)
    const auto start = std::chrono::steady_clock::now();
    auto built = build_bvh(*scene->mesh, trace->config, &recorder);
    if (!built) return nullptr;  // (the scene's own BVH was built with this config, so it passed)
    trace->bvh = std::move(*built);
    trace->build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    trace->steps = std::move(recorder.steps);
    trace->scene = std::move(scene);
    return trace;
}

BuildStepper::BuildStepper() = default;
BuildStepper::~BuildStepper() = default;

// [SECTION] Per frame: recording and charts on workers

void BuildStepper::update(AppState& state, const std::shared_ptr<const LoadedScene>& scene, bool wait) {
    // A tree from a file has no recorded construction: its nodes are stepped in the
    // file's order instead (see "A tree from a file" below).
    const bool file_tree = scene && scene->structure_file;
    file_scene_ = steps_nodes(scene.get());
    from_file_ = file_tree;
    // Off, or another scene: let go of the tree stepped (and the scene it keeps alive).
    if (file_trace_ && (!state.build_step.active || file_trace_->scene != scene)) release_file();
    // Work that finished for a stepper since turned off, or for a tree no longer
    // stepped, is dropped (a request is then made again when wanted): left waiting,
    // it would hold its tree (hundreds of MB at a million triangles) and count as
    // pending work for ever, so the window would never go idle.
    const bool wants_file = state.build_step.active && scene && file_scene_;
    const bool wants_trace = state.build_step.active && scene && !file_scene_ && !file_tree;
    if (!wants_file && (file_job_.busy() || file_job_.take())) release_file();
    if (!wants_trace && (trace_job_.busy() || trace_job_.take())) trace_requested_ = nullptr;
    if (!wants_trace && (chart_job_.busy() || chart_job_.take())) chart_requested_ = {};
    if (!wants_trace) {
        // Off: let go of a recording of another scene (a big mesh's takes ~230 bytes a node).
        if (trace_ && trace_->scene != scene) {
            trace_.reset();
            chart_.reset();
            chart_requested_ = {};
            trace_requested_ = nullptr;
        }
        if (file_scene_ && state.build_step.active) update_file(state, scene, wait);
        return;
    }
    if (trace_requested_ != scene.get()) {
        trace_requested_ = scene.get();
        trace_.reset();
        chart_.reset();
        chart_requested_ = {};
        trace_job_.submit([scene] { return record_build(scene); });
    }
    if (wait) trace_job_.wait();
    if (auto done = trace_job_.take()) trace_ = std::move(*done);
    if (!trace_ || trace_->steps.empty()) return;

    BuildStepSettings& s = state.build_step;
    s.step = std::clamp(s.step, 0, int(trace_->steps.size()) - 1);
    const ChartKey key{trace_.get(), s.step, chart_config(trace_->config, s)};
    if (!(key == chart_requested_)) {
        chart_requested_ = key;
        std::shared_ptr<const BuildTrace> trace = trace_;
        chart_job_.submit([key, trace] {
            const BuildStep& step = trace->steps[size_t(key.step)];
            const auto prims = std::span<const uint32_t>(trace->bvh.prim_ids).subspan(step.first, step.count);
            // A sweep on a big node lists the cheapest of each run of candidates: a
            // chart cannot show more points than it has pixels.
            return ChartResult{key, trace, compute_sah_chart(*trace->scene->mesh, prims, key.config, {.max_points = 600})};
        });
    }
    if (wait) chart_job_.wait();
    if (auto done = chart_job_.take()) chart_ = std::move(*done);
}

void BuildStepper::handle_keys(AppState& state) {
    if (state.build_step.active && file_trace_) return handle_file_keys(state);
    if (!state.build_step.active || !trace_ || trace_->steps.empty()) return;
    step_keys(state.build_step.step, int(trace_->steps.size()) - 1);
}

bool BuildStepper::shows_3d(const AppState& state) const {
    return state.build_step.active && ((trace_ && !trace_->steps.empty()) || (file_trace_ && file_node_));
}

bool BuildStepper::has_panel(const AppState& state, const LoadedScene* scene) const {
    if (!state.build_step.active) return false;
    if (steps_nodes(scene)) return true;
    return !(scene && scene->structure_file) && state.accel.type == AccelType::Bvh;
}

// [SECTION] Sidebar

bool BuildStepper::draw_sidebar(AppState& state, const LoadedScene* scene) {
    if (!ImGui::CollapsingHeader("Construction", ImGuiTreeNodeFlags_DefaultOpen)) return false;
    if (!state.accel.structure_file.empty()) {
        // Stepping our build here would show another tree than the one drawn and traced:
        // the file's own nodes are stepped, in the order it numbers them.
        const StructureFile* file =
            scene && scene->structure_file ? scene->structure_file->file.get() : nullptr;
        if (file && file->type == AccelType::Grid) {
            ImGui::TextDisabled("A grid from a file has no nodes to step.");
            state.build_step.active = false;  // (it would keep the arrow keys from the camera)
            return false;
        }
        stepper_switch("Step the file's nodes in order", state.build_step.active,
                       "Node by node as the file numbers them: a recursive builder's order.");
        return false;
    }
    if (state.accel.type == AccelType::Kd) {
        // Our KD tree node by node, in the order its build made them.
        stepper_switch("Step the KD build node by node", state.build_step.active,
                       "Each node's plane, its two cells and their triangles.");
        return false;
    }
    if (state.accel.type != AccelType::Bvh) {
        ImGui::TextDisabled("Step the build of a BVH split by split.");
        if (!ImGui::Button("Use a BVH")) return false;
        state.accel.type = AccelType::Bvh;
        state.build_step.active = true;
        return true;
    }
    stepper_switch("Step the BVH build", state.build_step.active, "The SAH chart of every split, with live sliders.");
    return false;
}

// [SECTION] The Construction panel

void BuildStepper::draw_panel(AppState& state, float x, float y, float w, float h, double view_aspect) {
    ImGui::SetNextWindowPos(ImVec2(x, y), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(w, h), ImGuiCond_Always);
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoBringToFrontOnFocus;
    bool open = true;
    // Three windows in the same place (ImGui names a window by its title).
    const char* title = !file_scene_ ? "Construction (BVH build)"
                        : from_file_ ? "Construction order (the file's nodes)"
                                     : "Construction (KD tree, node by node)";
    if (!ImGui::Begin(title, &open, flags)) {
        ImGui::End();
        return;
    }
    if (!open) state.build_step.active = false;
    if (file_scene_) {
        if (file_trace_) draw_file_panel(state, view_aspect);
        else ImGui::TextWrapped("Reading the tree ...");
        ImGui::End();
        return;
    }
    if (!trace_) {
        ImGui::TextWrapped("%s", state.accel.type == AccelType::Bvh ? "Recording the build ..."
                                                           : "The construction stepper needs a BVH (Structure: bvh).");
        ImGui::End();
        return;
    }
    if (trace_->steps.empty()) {
        ImGui::TextWrapped("The scene has no triangles: the build made no decisions.");
        ImGui::End();
        return;
    }
    BuildStepSettings& s = state.build_step;
    const int last = int(trace_->steps.size()) - 1;
    s.step = std::clamp(s.step, 0, last);
    const BuildStep& step = trace_->steps[size_t(s.step)];

    // Timeline: |< < > >|, the next split (leaves skipped) and the scrubber.
    timeline_buttons(s.step, last, [&](int k) { return trace_->bvh.nodes[trace_->steps[size_t(k)].node].count == 0; });
    // Deep nodes are small: bring the camera to this one (F brings back the whole scene).
    if (ImGui::Button("frame node") && state.camera) frame_bounds(*state.camera, step.bounds, view_aspect);
    if (trace_->scene_width != 2)
        ImGui::TextWrapped("The binary build; the %d-wide tree is collapsed from it (Children per node).",
                           trace_->scene_width);
    ImGui::SetNextItemWidth(-FLT_MIN);
    const std::string scrub_format = "decision %d (of 0.." + std::to_string(last) + ")";
    ImGui::SliderInt("##scrub", &s.step, 0, last, scrub_format.c_str(), ImGuiSliderFlags_AlwaysClamp);

    // The node and the builder's decision.
    const bool leaf = trace_->bvh.nodes[step.node].is_leaf();
    ImGui::TextWrapped("Node %u, depth %u: %u triangles (%s, %s)", step.node, step.depth, step.count,
                std::string(to_string(trace_->config.builder)).c_str(), leaf ? "leaf" : "split");
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextUnformatted(explain(step.decision, trace_->config.max_leaf_size).c_str());
    if (!leaf) {
        // Each child's surface area over the node's: the SAH's chance that a ray through
        // the node's box also meets the child's box (the lecture's S_A/S_N, S_B/S_N).
        const BvhNode& node = trace_->bvh.nodes[step.node];
        const float area = node.bounds.area();
        const float p_left = SahCostModel::hit_probability(trace_->bvh.nodes[node.first].bounds.area(), area);
        const float p_right = SahCostModel::hit_probability(trace_->bvh.nodes[node.first + 1].bounds.area(), area);
        const uint32_t n_left = step.left_count, n_right = step.count - step.left_count;
        swatch(im(kLeftColour));
        ImGui::Text("left %u, S_A/S_N = %.2f", n_left, double(p_left));
        swatch(im(kRightColour));
        ImGui::Text("right %u, S_B/S_N = %.2f", n_right, double(p_right));
        if (step.axis >= 0)
            ImGui::Text("split at %s = %.4g, cost %s", kAxisNames[step.axis], double(step.split_position),
                        cost_text(step.split_cost).c_str());
        else
            ImGui::Text("split by index, cost %s", cost_text(step.split_cost).c_str());
        // The same cost (the children's own boxes), term by term as the lecture writes it.
        const SahCostModel model = trace_->config.sah_model();
        if (model.leaf_lanes > 1)
            ImGui::TextDisabled("The wide BVH tests a leaf's triangles %u at a time: N counts tests, ceil(N / %u).",
                                model.leaf_lanes, model.leaf_lanes);
        ImGui::TextDisabled("C = C_trav + S_A/S_N N_A C_isect + S_B/S_N N_B C_isect = %s + %.2f x %u x %s + %.2f x %u x %s "
                            "= %s (a leaf: %s)",
                            cost_text(model.cost_trav).c_str(), double(p_left), model.tests(n_left),
                            cost_text(model.cost_isect).c_str(), double(p_right), model.tests(n_right),
                            cost_text(model.cost_isect).c_str(),
                            cost_text(model.split_cost(area, trace_->bvh.nodes[node.first].bounds.area(), n_left,
                                                       trace_->bvh.nodes[node.first + 1].bounds.area(), n_right))
                                .c_str(),
                            cost_text(model.leaf_cost(step.count)).c_str());
    }
    ImGui::PopTextWrapPos();
    ImGui::Separator();

    // The chart (the last one computed; marked while a newer one is on its way).
    const bool chart_current = chart_ && chart_->key == chart_requested_;
    if (chart_) {
        draw_chart(chart_->chart, step, ImGui::GetContentRegionAvail().x);
        if (!chart_current) ImGui::TextDisabled("updating ...");
    } else {
        ImGui::TextDisabled("computing the chart ...");
    }

    // Live sliders: the chart's parameters (the tree stays as built).
    ImGui::Separator();
    const BvhConfig built = trace_->config;
    BvhConfig c = chart_config(built, s);
    ImGui::PushItemWidth(ImGui::GetContentRegionAvail().x * 0.5f);
    if (c.builder == BvhBuilder::SahSweep) {
        ImGui::TextDisabled("sah-sweep: every centroid is a candidate (no B)");
    } else if (ImGui::SliderInt("B (bins)", &c.bins, kBvhMinBins, kBvhMaxBins, "%d", ImGuiSliderFlags_AlwaysClamp)) {
        s.bins = c.bins;
    }
    if (ImGui::SliderFloat("C_trav", &c.cost_trav, 0.0f, 10.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp))
        s.cost_trav = c.cost_trav;
    if (ImGui::SliderFloat("C_isect", &c.cost_isect, 0.05f, 10.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp))
        s.cost_isect = c.cost_isect;
    ImGui::PopItemWidth();
    const bool differs = !(chart_config(built, s) == built);
    if (differs) {
        if (ImGui::Button("Back to the tree's parameters")) {
            s.bins.reset();
            s.cost_trav.reset();
            s.cost_isect.reset();
        }
        ImGui::TextDisabled("The sliders change the chart only; the tree stays as built.");
    } else {
        ImGui::TextDisabled("Tree built with B = %d, C_trav = %.2f, C_isect = %.2f", built.bins, double(built.cost_trav),
                            double(built.cost_isect));
    }
    ImGui::End();
}

namespace {

/// Which planes are charted, the builder's note, and the verdict in one sentence.
void draw_chart_heading(const SahChart& chart) {
    // What the candidates are.
    const char* what = chart.sweep ? "every centroid" : "the B - 1 bucket boundaries";
    if (chart.sweep)
        ImGui::Text("SAH cost of each plane (%s) per axis", what);
    else
        ImGui::Text("SAH cost of each plane (B = %d: %d per axis)", chart.bins, chart.bins - 1);
    if (!is_sah(chart.builder))
        ImGui::TextDisabled("(%s does not use the SAH; the chart shows what binned SAH would weigh)",
                            std::string(to_string(chart.builder)).c_str());
    // The verdict under these parameters, first: the chart's point in one sentence.
    const bool light = ImGui::GetStyle().Colors[ImGuiCol_WindowBg].x > 0.5f;  // the light theme: darker text
    const ImU32 split_colour = light ? IM_COL32(20, 120, 40, 255) : kBest;
    const ImU32 leaf_colour = light ? IM_COL32(170, 80, 0, 255) : IM_COL32(255, 190, 90, 255);
    ImGui::PushStyleColor(ImGuiCol_Text,
                          ImGui::ColorConvertU32ToFloat4(chart.verdict == ChartVerdict::Split ? split_colour : leaf_colour));
    ImGui::TextUnformatted(chart.verdict_text.c_str());
    ImGui::PopStyleColor();

}

/// The cost scale of the chart: one y range for the three axes, so their curves
/// compare, from the cheapest value shown to the dearest (the leaf line always in
/// view), with `pad` of margin on each side.
struct CostRange {
    float lo = 0, hi = 0, pad = 0;
};
CostRange cost_range(const SahChart& chart) {
    float y_lo = chart.leaf_cost, y_hi = chart.leaf_cost;
    for (const SahChartAxis& a : chart.axes)
        for (float c : a.costs)
            if (std::isfinite(c)) {
                y_lo = std::min(y_lo, c);
                y_hi = std::max(y_hi, c);
            }
    for (const HeuristicCut* cut : {&chart.median, &chart.midpoint})
        if (cut->valid && std::isfinite(cut->cost)) {
            y_lo = std::min(y_lo, cut->cost);
            y_hi = std::max(y_hi, cut->cost);
        }
    if (!(y_hi > y_lo)) {
        y_hi = y_lo + std::max(1.0f, std::abs(y_lo) * 0.1f);
        y_lo -= std::max(1.0f, std::abs(y_lo) * 0.1f) * 0.5f;
    }
    const float pad = 0.08f * (y_hi - y_lo);
    y_lo -= pad;
    y_hi += pad;
    return {y_lo, y_hi, pad};
}

/// One axis's plot: the cost of every candidate plane, the leaf line, the heuristics'
/// cuts, the cheapest plane, the tree's own split, and the hovered plane's numbers.
void draw_axis_chart(const SahChart& chart, const BuildStep& step, int axis, float width, const CostRange& range) {
    const float y_lo = range.lo, y_hi = range.hi, pad = range.pad;
    const float font = ImGui::GetFontSize();
    const float label_w = ImGui::CalcTextSize("00000.0").x + 0.5f * font;
    const float plot_h = 3.8f * font;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImU32 label_colour = ImGui::GetColorU32(ImGuiCol_Text);  // labels outside the (always dark) plot
    const float line = std::max(2.0f, 0.125f * font);               // thicker with the UI scale (projectors)
    const SahChartAxis& a = chart.axes[size_t(axis)];
    ImGui::Text("%s axis", kAxisNames[axis]);
    if (a.subsampled) {
        ImGui::SameLine();
        ImGui::TextDisabled("(%zu of %zu planes shown: the cheapest of every %zu)", a.positions.size(), a.candidates,
                            a.stride);
    }
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const ImVec2 p0(origin.x + label_w, origin.y), p1(origin.x + width - 0.5f * font, origin.y + plot_h);
    ImGui::Dummy(ImVec2(width, plot_h + 1.1f * ImGui::GetTextLineHeight()));
    draw->AddRectFilled(p0, p1, kPlotBg);
    draw->AddRect(p0, p1, kPlotFrame);
    auto y_of = [&](float cost) { return p1.y - (cost - y_lo) / (y_hi - y_lo) * (p1.y - p0.y); };
    // Cost labels at the left: the top and bottom of the range.
    draw->AddText(ImVec2(origin.x, p0.y), label_colour, cost_text(y_hi - pad).c_str());
    draw->AddText(ImVec2(origin.x, p1.y - ImGui::GetTextLineHeight()), label_colour, cost_text(y_lo + pad).c_str());
    // Leaf cost: a horizontal line across every axis's chart.
    const float leaf_y = y_of(chart.leaf_cost);
    draw->AddLine(ImVec2(p0.x, leaf_y), ImVec2(p1.x, leaf_y), kLeafLine, line);
    if (!a.usable) {
        const char* text = "all centroids equal on this axis: no plane";
        const ImVec2 size = ImGui::CalcTextSize(text);
        draw->AddText(ImVec2(0.5f * (p0.x + p1.x - size.x), 0.5f * (p0.y + p1.y) - size.y), kAxisText, text);
        return;
    }
    const float x_lo = a.lo, x_hi = a.hi;
    auto x_of = [&](float pos) { return p0.x + (pos - x_lo) / (x_hi - x_lo) * (p1.x - p0.x); };
    // Position labels under the plot: the centroid bounds.
    const float text_y = p1.y + 0.1f * font;
    draw->AddText(ImVec2(p0.x, text_y), label_colour, text_of("%.4g", double(x_lo)).c_str());
    const std::string hi_text = text_of("%.4g", double(x_hi));
    draw->AddText(ImVec2(p1.x - ImGui::CalcTextSize(hi_text.c_str()).x, text_y), label_colour, hi_text.c_str());
    // Heuristic cuts: vertical lines on the axis they would cut.
    auto vline = [&](const HeuristicCut& cut, ImU32 colour, const char* label, float label_row) {
        if (!cut.valid || cut.axis != axis) return;
        const float x = x_of(cut.position);
        draw->AddLine(ImVec2(x, p0.y), ImVec2(x, p1.y), colour, line);
        draw->AddText(ImVec2(x + 3.0f, p0.y + label_row * ImGui::GetTextLineHeight()), colour, label);
    };
    vline(chart.midpoint, kMidpoint, "midpoint", 0.0f);
    vline(chart.median, kMedian, "median", 1.0f);
    // The curve: finite costs joined, +inf (a side would be empty) as ticks at the bottom.
    const bool dots = a.positions.size() <= 80;
    ImVec2 prev;
    bool have_prev = false;
    for (size_t i = 0; i < a.positions.size(); ++i) {
        const float x = x_of(a.positions[i]);
        if (!std::isfinite(a.costs[i])) {
            draw->AddLine(ImVec2(x, p1.y - 0.35f * font), ImVec2(x, p1.y), kEmpty, 0.75f * line);
            have_prev = false;
            continue;
        }
        const ImVec2 p(x, y_of(a.costs[i]));
        if (have_prev) draw->AddLine(prev, p, kCurve, line);
        if (dots) draw->AddCircleFilled(p, 0.16f * font, kCurve);
        prev = p;
        have_prev = true;
    }
    // Hover: the nearest plane's numbers.
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    if (!a.positions.empty() && ImGui::IsWindowHovered() && mouse.x >= p0.x && mouse.x <= p1.x && mouse.y >= p0.y &&
        mouse.y <= p1.y) {
        size_t nearest = 0;
        for (size_t i = 1; i < a.positions.size(); ++i)
            if (std::abs(x_of(a.positions[i]) - mouse.x) < std::abs(x_of(a.positions[nearest]) - mouse.x)) nearest = i;
        const float x = x_of(a.positions[nearest]);
        draw->AddLine(ImVec2(x, p0.y), ImVec2(x, p1.y), kAxisText, 1.0f);
        const uint32_t left = a.left_counts[nearest];
        if (std::isfinite(a.costs[nearest]))
            ImGui::SetTooltip("%s = %.4g: cost %s (%u left | %u right)", kAxisNames[axis], double(a.positions[nearest]),
                              cost_text(a.costs[nearest]).c_str(), left, chart.count - left);
        else
            ImGui::SetTooltip("%s = %.4g: one side would be empty (or the plane falls between equal centroids)",
                              kAxisNames[axis], double(a.positions[nearest]));
    }
    // The cheapest plane under these parameters.
    if (chart.best_axis == axis) {
        const float x = x_of(chart.best_position);
        draw->AddLine(ImVec2(x, p0.y), ImVec2(x, p1.y), kBest, 0.75f * line);
        draw->AddCircleFilled(ImVec2(x, y_of(chart.best_cost)), 0.32f * font, kBest);
    }
    // The tree's own split, when the sliders moved the cheapest plane elsewhere.
    if (step.axis == axis && !(chart.best_axis == axis && chart.best_position == step.split_position)) {
        const float x = x_of(step.split_position);
        for (float yy = p0.y; yy < p1.y; yy += 0.5f * font)
            draw->AddLine(ImVec2(x, yy), ImVec2(x, std::min(p1.y, yy + 0.25f * font)), kBest, line);
    }
}

/// The legend under the plots, with the numbers.
void draw_chart_legend(const SahChart& chart) {
    swatch(kLeafLine);
    ImGui::Text("leaf: N x C_isect = %s%s", cost_text(chart.leaf_cost).c_str(), chart.model.leaf_lanes > 1 ? " (N in tests of 4)" : "");
    swatch(kBest);
    if (chart.best_axis >= 0)
        ImGui::Text("cheapest: %s = %.4g, cost %s (%u | %u)", kAxisNames[chart.best_axis], double(chart.best_position),
                    cost_text(chart.best_cost).c_str(), chart.best_left_count, chart.count - chart.best_left_count);
    else
        ImGui::TextUnformatted("cheapest: no plane separates the centroids");
    for (const auto& [cut, colour, name] : {std::tuple{&chart.median, kMedian, "median"},
                                           std::tuple{&chart.midpoint, kMidpoint, "midpoint"}}) {
        swatch(colour);
        if (cut->valid)
            ImGui::Text("%s: %s = %.4g, cost %s (%u | %u)%s", name, kAxisNames[cut->axis], double(cut->position),
                        cost_text(cut->cost).c_str(), cut->left_count, chart.count - cut->left_count,
                        cut->median_fallback ? ", the median: the middle left a side empty" : "");
        else
            ImGui::Text("%s: no plane (all centroids equal)", name);
    }
}

}  // namespace

void BuildStepper::draw_chart(const SahChart& chart, const BuildStep& step, float width) {
    ImGui::PushTextWrapPos(0.0f);
    draw_chart_heading(chart);
    const CostRange range = cost_range(chart);
    for (int axis = 0; axis < 3; ++axis) draw_axis_chart(chart, step, axis, width, range);
    draw_chart_legend(chart);
    ImGui::PopTextWrapPos();
}

// [SECTION] 3D: the node's triangles and boxes

void BuildStepper::upload_step(const BuildStep& step, Rgb background) {
    const Mesh& mesh = *trace_->scene->mesh;
    const bool leaf = trace_->bvh.nodes[step.node].is_leaf();
    const uint32_t left_end = leaf ? step.first + step.count : step.first + step.left_count;
    auto subset = [&](uint32_t begin, uint32_t end) {
        return mesh_subset(mesh, std::span<const uint32_t>(trace_->bvh.prim_ids).subspan(begin, end - begin));
    };
    if (!left_tris_) left_tris_ = std::make_unique<MeshBuffer>();
    if (!right_tris_) right_tris_ = std::make_unique<MeshBuffer>();
    if (!boxes_) boxes_ = std::make_unique<BoxBuffer>();
    left_tris_->upload(subset(step.first, left_end));
    right_tris_->upload(subset(left_end, step.first + step.count));
    std::vector<BoxInstance> boxes = {node_box(step.bounds, node_box_colour(background))};
    std::vector<ColouredQuad> quads;
    if (!leaf && step.axis >= 0) quads.push_back(split_plane_quad(step.bounds, step.axis, step.split_position));
    if (!plane_) plane_ = std::make_unique<ColouredBuffer>();
    plane_->upload_quads(quads);
    if (!leaf) {
        const BvhNode& node = trace_->bvh.nodes[step.node];
        const Aabb& l = trace_->bvh.nodes[node.first].bounds;
        const Aabb& r = trace_->bvh.nodes[node.first + 1].bounds;
        boxes.push_back({l.lo, l.hi, kLeftColour});
        boxes.push_back({r.lo, r.hi, kRightColour});
    }
    boxes_->upload(boxes);
}

void BuildStepper::draw_3d(Renderer& renderer, const MeshBuffer& mesh, int step_index, Rgb background) {
    if (file_trace_ && file_node_) return draw_file_3d(renderer, mesh, background);
    if (!trace_ || trace_->steps.empty()) {
        renderer.draw_mesh(mesh, {});
        return;
    }
    shown_step_ = std::clamp(step_index, 0, int(trace_->steps.size()) - 1);
    if (uploaded_trace_ != trace_.get() || uploaded_step_ != shown_step_ || !(uploaded_background_ == background)) {
        upload_step(trace_->steps[size_t(shown_step_)], background);
        uploaded_file_node_.reset();  // the buffers no longer hold a file's node
        uploaded_trace_ = trace_.get();
        uploaded_step_ = shown_step_;
        uploaded_background_ = background;
    }
    const BuildStep& step = trace_->steps[size_t(shown_step_)];
    const bool leaf = trace_->bvh.nodes[step.node].is_leaf();
    // The node's triangles first, in their side's colour; then the whole mesh dimmed:
    // with the same vertices and shader it lands on the same depths, fails the depth
    // test there, and fills in only the triangles of other nodes.
    renderer.draw_mesh(*left_tris_, {.base_colour = leaf ? kLeafTriangles : Rgb{kLeftColour.r, kLeftColour.g, kLeftColour.b}});
    renderer.draw_mesh(*right_tris_, {.base_colour = Rgb{kRightColour.r, kRightColour.g, kRightColour.b}});
    renderer.draw_mesh(mesh, {.base_colour = kDimMesh});
    renderer.draw_quads(*plane_);
    renderer.draw_boxes(*boxes_);
}

}  // namespace accelviz

namespace accelviz {

// [SECTION] A tree from a file: its nodes in the file's order

namespace {

/// A child's colour: the binary tree's two, then six more for a wide node's lanes.
constexpr std::array<Rgba8, kStructureMaxArity> kChildColours = {{
    kLeftColour, kRightColour, {235, 110, 235, 255}, {90, 215, 235, 255},
    {190, 230, 70, 255}, {255, 110, 130, 255}, {165, 130, 255, 255}, {215, 185, 140, 255},
}};

Rgb rgb(Rgba8 c) { return {c.r, c.g, c.b}; }

/// The KD tree a trace steps when it is our own (not a file's).
const KdTree* our_kd_tree(const FileOrderTrace& trace) {
    return trace.check || !trace.scene->accel ? nullptr : structure_if<KdTree>(*trace.scene->accel);
}

/// The costs our KD tree's chart weighs with: the tree's, or the sliders'.
KdConfig kd_chart_config(const KdTree& tree, const BuildStepSettings& s) {
    KdConfig c = tree.build_config;
    if (s.cost_trav) c.cost_trav = std::max(0.0f, *s.cost_trav);
    if (s.cost_isect && *s.cost_isect > 0.0f) c.cost_isect = *s.cost_isect;
    return c;
}

}  // namespace

/// Node `key.step` of the trace's tree (clamped), and our KD tree's chart of it,
/// computed on the worker.
BuildStepper::FileStepResult BuildStepper::file_step_of(const std::shared_ptr<const FileOrderTrace>& trace,
                                                        const FileStepKey& key) {
    FileStepResult out{trace, nullptr, nullptr};
    if (!trace || trace->order.size() == 0) return out;
    const uint64_t node = uint64_t(std::clamp<int64_t>(key.step, 0, int64_t(trace->order.size()) - 1));
    // The costs are the panel's to weigh (its sliders); the step keeps the counts and areas.
    out.node = std::make_shared<const FileNodeStep>(
        file_node_step(*trace->file, trace->order, node, trace->scene->mesh->triangle_count(), SahCosts{}));
    if (const KdTree* kd = our_kd_tree(*trace); kd && kd->build_config.builder == KdBuilder::Sah) {
        KdConfig c = kd->build_config;
        c.cost_trav = key.cost_trav;
        c.cost_isect = key.cost_isect;
        // A chart cannot show more points than it has pixels.
        out.kd_chart = std::make_shared<const KdSahChart>(kd_sah_chart(*trace->scene->mesh, *kd, uint32_t(node), c, 600));
    }
    return out;
}

namespace {

/// The tree of `scene` to step node by node: its file's, or our KD tree exported.
std::shared_ptr<const FileOrderTrace> node_order_of(const std::shared_ptr<const LoadedScene>& scene) {
    auto trace = std::make_shared<FileOrderTrace>();
    trace->scene = scene;
    if (scene->structure_file) {
        trace->file = scene->structure_file->file;
        trace->check = &scene->structure_file->check;
    } else {
        auto ours = export_structure(*scene->accel, *scene->mesh, {});
        if (!ours) return nullptr;  // (steps_nodes: a KD tree, which exports)
        trace->file = std::make_shared<const StructureFile>(std::move(*ours));
    }
    trace->order = file_tree_order(*trace->file);
    return trace;
}

}  // namespace

bool steps_nodes(const LoadedScene* scene) {
    if (!scene) return false;
    if (scene->structure_file) return scene->structure_file->file->type != AccelType::Grid;
    return scene->accel && structure_if<KdTree>(*scene->accel) != nullptr;
}

void BuildStepper::release_file() {
    file_trace_.reset();
    file_node_.reset();
    kd_chart_.reset();
    file_requested_ = nullptr;
    file_step_requested_ = {};
    uploaded_file_node_.reset();
}

void BuildStepper::update_file(AppState& state, const std::shared_ptr<const LoadedScene>& scene, bool wait) {
    int& step = state.build_step.step;
    step = std::max(step, 0);
    // The KD chart's costs: our tree's, or the sliders' (a file's tree has no chart).
    FileStepKey key{step, 0, 0};
    if (const KdTree* kd = scene->accel && !scene->structure_file ? structure_if<KdTree>(*scene->accel) : nullptr) {
        const KdConfig c = kd_chart_config(*kd, state.build_step);
        key.cost_trav = c.cost_trav;
        key.cost_isect = c.cost_isect;
    }
    if (file_requested_ != scene.get()) {
        release_file();
        file_requested_ = scene.get();
        file_step_requested_ = key;
        file_job_.submit([scene, key] { return file_step_of(node_order_of(scene), key); });
    } else if (file_trace_ && file_trace_->order.size() > 0) {
        key.step = step = std::min(step, int(file_trace_->order.size()) - 1);
        if (!(key == file_step_requested_)) {
            file_step_requested_ = key;
            std::shared_ptr<const FileOrderTrace> trace = file_trace_;
            file_job_.submit([trace, key] { return file_step_of(trace, key); });
        }
    }
    if (wait) file_job_.wait();
    if (auto done = file_job_.take()) {
        file_trace_ = std::move(done->trace);
        file_node_ = std::move(done->node);
        kd_chart_ = std::move(done->kd_chart);
    }
    if (file_trace_ && file_trace_->order.size() > 0) step = std::min(step, int(file_trace_->order.size()) - 1);
}

void BuildStepper::handle_file_keys(AppState& state) {
    if (file_trace_->order.size() > 0) step_keys(state.build_step.step, int(file_trace_->order.size()) - 1);
}

void BuildStepper::draw_file_panel(AppState& state, double view_aspect) {
    const FileTreeOrder& order = file_trace_->order;
    const StructureFile& file = *file_trace_->file;
    const bool kd = file.type == AccelType::Kd;
    if (order.size() == 0) {
        ImGui::TextWrapped("The tree has no nodes.");
        return;
    }
    BuildStepSettings& s = state.build_step;
    const int last = int(order.size()) - 1;
    s.step = std::clamp(s.step, 0, last);

    // Timeline, as over our build.
    timeline_buttons(s.step, last, [&](int k) {
        return kd ? !file.kd_nodes[size_t(k)].is_leaf() : file.bvh_nodes[size_t(k)].interior;
    });
    if (ImGui::Button("frame node") && state.camera && file_node_ && finite_box(file_node_->box) &&
        !file_node_->box.empty())
        frame_bounds(*state.camera, file_node_->box, view_aspect);
    ImGui::SetNextItemWidth(-FLT_MIN);
    const std::string scrub_format = "node %d (of 0.." + std::to_string(last) + ")";
    ImGui::SliderInt("##scrub", &s.step, 0, last, scrub_format.c_str(), ImGuiSliderFlags_AlwaysClamp);
    ImGui::PushTextWrapPos(0.0f);
    // One line; the whole story on hover (the panel's room is for the node and its chart).
    if (file_trace_->check) {
        ImGui::TextDisabled("The nodes as the file numbers them (hover: why)");
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("A builder that writes each node as it makes it (a node, then its first child's\n"
                              "subtree) numbers them in construction order: stepping by number replays its build.");
    } else {
        ImGui::TextDisabled("The nodes as our build made them (hover: the order)");
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("A split makes its two children (below, above the plane) together; every node comes\n"
                              "after its parent: the top levels first, then each subtree under them, the lower\n"
                              "before the upper. A triangle that straddles the plane goes to both.");
    }

    const FileNodeStep* node = file_node_.get();
    if (!node || node->node != uint64_t(s.step)) {
        ImGui::TextUnformatted("reading the node ...");
        if (!node) {
            ImGui::PopTextWrapPos();
            return;
        }
    }
    // Where the node is in the tree.
    if (!node->reached)
        ImGui::Text("Node %llu: no path from the root (node 0) leads here", (unsigned long long)node->node);
    else if (node->parent)
        ImGui::Text("Node %llu, depth %u, child of node %llu", (unsigned long long)node->node, node->depth,
                    (unsigned long long)*node->parent);
    else
        ImGui::Text("Node %llu: the root", (unsigned long long)node->node);

    // What it holds, and what its split costs (the lecture's SAH, the file's boxes).
    // Our KD tree: the costs it was built with, and its bonus for cutting off empty
    // space; a file's tree: unit costs (its builder's are not in the file).
    const KdTree* ours = our_kd_tree(*file_trace_);
    const KdConfig built = ours ? kd_chart_config(*ours, s) : KdConfig{};
    const SahCostModel model{ours ? built.cost_trav : s.cost_trav.value_or(1.0f),
                             ours ? built.cost_isect : s.cost_isect.value_or(1.0f),
                             ours ? uint32_t(built.leaf_lanes) : 1u};  // our KD tree counts tests (kd_sah.h)
    const float empty_bonus = ours ? built.empty_bonus : 0.0f;
    const uint32_t n = uint32_t(node->triangle_count);
    if (node->leaf) {
        ImGui::Text("Leaf: %u triangles, cost N x C_isect%s = %s", n, model.leaf_lanes > 1 ? " (N in tests of 4)" : "",
                    cost_text(model.leaf_cost(n)).c_str());
    } else {
        if (kd)
            ImGui::Text("Split at %s = %.4g: %u triangles under it", kAxisNames[node->axis], double(node->split), n);
        else
            ImGui::Text("Interior, %zu children: %u triangles under it", node->children.size(), n);
        std::string terms = cost_text(model.cost_trav);
        float cost = model.cost_trav;
        for (size_t k = 0; k < node->children.size(); ++k) {
            const auto count = uint32_t(node->triangles[k].size());
            const float p = node->child_probability[k];
            swatch(im(kChildColours[k % kChildColours.size()]));
            const char* side = !kd                                                      ? ""
                               : node->children[k] == file.kd_nodes[node->node].children[0] ? "below, "
                                                                                            : "above, ";
            ImGui::Text("%snode %llu: %u triangles, S/S_N = %.2f", side, (unsigned long long)node->children[k],
                        count, double(p));
            cost += p * float(model.tests(count)) * model.cost_isect;
            terms += text_of(" + %.2f", double(p)) + " x " + std::to_string(model.tests(count)) + " x " +
                     cost_text(model.cost_isect);
        }
        if (kd) {
            // The KD tree's lesson: a primitive in several nodes.
            size_t listed = 0;
            for (const auto& under : node->triangles) listed += under.size();
            if (listed > n)
                ImGui::Text("%zu triangles straddle the plane: they are in both", listed - size_t(n));
        }
        bool a_side_empty = false;
        for (const auto& under : node->triangles) a_side_empty |= under.empty();
        if (a_side_empty && empty_bonus > 0.0f) {
            // The KD build's SAH: a plane that cuts off empty space costs (1 - bonus) of it.
            cost *= 1.0f - empty_bonus;
            terms = "(" + terms + ") x (1 - " + cost_text(empty_bonus) + ": a side is empty)";
        }
        if (node->children_left_out > 0)
            ImGui::Text("... and %llu more children (a node may have 8 at most)",
                        (unsigned long long)node->children_left_out);
        ImGui::TextDisabled("C = C_trav + sum S_c/S_N N_c C_isect%s = %s = %s (a leaf: %s)",
                            model.leaf_lanes > 1 ? " (N_c in tests: ceil(N / 4))" : "", terms.c_str(),
                            cost_text(cost).c_str(), cost_text(model.leaf_cost(n)).c_str());
        if (cost >= model.leaf_cost(n))
            ImGui::TextDisabled("The split costs more than a leaf would: the SAH would stop here.");
    }

    // Our KD tree: the SAH of every candidate plane of this node (the builder's sweep).
    if (kd_chart_ && kd_chart_->node == node->node) {
        ImGui::Separator();
        draw_kd_chart(*kd_chart_, *node, ImGui::GetContentRegionAvail().x);
    }

    // What check says of this node or its children (a child's box sticking out of
    // this one), in the overlay's red.
    const StructureCheck* check = file_trace_->check;
    if (check && std::binary_search(check->bad_nodes.begin(), check->bad_nodes.end(), node->node)) {
        ImGui::PushStyleColor(ImGuiCol_Text, im(kFaultRed));
        bool listed = false;
        for (const StructureProblem& p : check->problems) {
            const bool about_child =
                p.node && std::find(node->children.begin(), node->children.end(), *p.node) != node->children.end();
            if (p.node == node->node || about_child) {
                ImGui::Bullet();
                ImGui::TextWrapped("%s", p.message.c_str());
                listed = true;
            }
        }
        if (!listed) ImGui::TextUnformatted("A problem involves this node (accelviz check lists them all).");
        ImGui::PopStyleColor();
    }
    ImGui::PopTextWrapPos();

    // The costs' sliders: the numbers above follow them.
    ImGui::Separator();
    float trav = model.cost_trav, isect = model.cost_isect;
    ImGui::PushItemWidth(ImGui::GetContentRegionAvail().x * 0.5f);
    if (ImGui::SliderFloat("C_trav", &trav, 0.0f, 10.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp)) s.cost_trav = trav;
    if (ImGui::SliderFloat("C_isect", &isect, 0.05f, 10.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp))
        s.cost_isect = isect;
    ImGui::PopItemWidth();
    if ((s.cost_trav || s.cost_isect) && ImGui::Button(ours ? "Back to the tree's costs" : "Back to unit costs")) {
        s.cost_trav.reset();
        s.cost_isect.reset();
    }
}

void BuildStepper::draw_kd_chart(const KdSahChart& chart, const FileNodeStep& node, float width) {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::Text("SAH cost of each plane (every reference box's side) per axis");
    ImGui::TextDisabled("C = C_trav + C_isect (A_below N_below + A_above N_above) / A, x (1 - %.2f) when a side "
                        "is empty%s",
                        double(chart.config.empty_bonus),
                        chart.config.leaf_lanes > 1 ? "; N counts tests: a leaf tests its triangles 4 at a time, ceil(N / 4)"
                                                    : "");
    // One cost scale for the three axes, from the cheapest plane to a little over the leaf.
    float lo = chart.leaf_cost, hi = chart.leaf_cost;
    for (const KdSahChartAxis& a : chart.axes)
        for (float c : a.costs)
            if (std::isfinite(c)) lo = std::min(lo, c);
    hi = std::max(hi * 1.15f, lo + 1e-3f);
    const float font = ImGui::GetFontSize();
    const float height = 3.2f * font, line = std::max(1.0f, font / 12.0f);
    ImDrawList* draw = ImGui::GetWindowDrawList();
    for (int axis = 0; axis < 3; ++axis) {
        const KdSahChartAxis& a = chart.axes[size_t(axis)];
        ImGui::Text("%s: %zu planes%s", kAxisNames[axis], a.candidates, a.subsampled ? " (the cheapest of each run shown)" : "");
        const ImVec2 p0 = ImGui::GetCursorScreenPos();
        const ImVec2 p1(p0.x + width, p0.y + height);
        ImGui::Dummy(ImVec2(width, height));
        draw->AddRectFilled(p0, p1, kPlotBg);
        draw->AddRect(p0, p1, kPlotFrame);
        const float span = a.hi > a.lo ? a.hi - a.lo : 1.0f;
        auto x_of = [&](float v) { return p0.x + (v - a.lo) / span * (p1.x - p0.x); };
        auto y_of = [&](float c) { return p1.y - (std::min(c, hi) - lo) / (hi - lo) * (p1.y - p0.y); };
        // The leaf's cost: a plane under this line pays.
        draw->AddLine(ImVec2(p0.x, y_of(chart.leaf_cost)), ImVec2(p1.x, y_of(chart.leaf_cost)), kLeafLine, line);
        for (size_t i = 1; i < a.positions.size(); ++i)
            draw->AddLine(ImVec2(x_of(a.positions[i - 1]), y_of(a.costs[i - 1])), ImVec2(x_of(a.positions[i]), y_of(a.costs[i])),
                          kCurve, line);
        if (chart.best_axis == axis)
            draw->AddCircleFilled(ImVec2(x_of(chart.best_position), y_of(chart.best_cost)), 0.32f * font, kBest);
        // The tree's plane, dashed (it is the cheapest under the tree's own costs).
        if (node.axis == axis) {
            const float x = x_of(node.split);
            for (float yy = p0.y; yy < p1.y; yy += 0.5f * font)
                draw->AddLine(ImVec2(x, yy), ImVec2(x, std::min(p1.y, yy + 0.25f * font)), kBest, line);
        }
        const ImVec2 mouse = ImGui::GetIO().MousePos;
        if (!a.positions.empty() && ImGui::IsWindowHovered() && mouse.x >= p0.x && mouse.x <= p1.x &&
            mouse.y >= p0.y && mouse.y <= p1.y) {
            size_t nearest = 0;
            for (size_t i = 1; i < a.positions.size(); ++i)
                if (std::abs(x_of(a.positions[i]) - mouse.x) < std::abs(x_of(a.positions[nearest]) - mouse.x)) nearest = i;
            ImGui::SetTooltip("%s = %.4g: cost %s (%u below | %u above)", kAxisNames[axis], double(a.positions[nearest]),
                              cost_text(a.costs[nearest]).c_str(), a.below[nearest], a.above[nearest]);
        }
    }
    swatch(kLeafLine);
    ImGui::Text("leaf: N x C_isect = %s%s", cost_text(chart.leaf_cost).c_str(), chart.config.leaf_lanes > 1 ? " (N in tests of 4)" : "");
    swatch(kBest);
    if (chart.best_axis >= 0)
        ImGui::Text("cheapest: %s = %.4g, cost %s (%u | %u)%s", kAxisNames[chart.best_axis], double(chart.best_position),
                    cost_text(chart.best_cost).c_str(), chart.best_below, chart.best_above,
                    chart.best_cost < chart.leaf_cost ? "" : ": no plane beats the leaf");
    else
        ImGui::TextUnformatted("cheapest: no plane lies inside the cell");
    ImGui::PopTextWrapPos();
}

void BuildStepper::draw_file_3d(Renderer& renderer, const MeshBuffer& mesh, Rgb background) {
    const FileNodeStep& node = *file_node_;
    if (uploaded_file_node_ != file_node_ || !(uploaded_background_ == background)) {
        const Mesh& scene_mesh = *file_trace_->scene->mesh;
        child_tris_.resize(node.triangles.size());
        for (size_t k = 0; k < node.triangles.size(); ++k) {
            if (!child_tris_[k]) child_tris_[k] = std::make_unique<MeshBuffer>();
            child_tris_[k]->upload(mesh_subset(scene_mesh, node.triangles[k]));
        }
        const StructureCheck* check = file_trace_->check;
        const bool faulty = check && std::binary_search(check->bad_nodes.begin(), check->bad_nodes.end(), node.node);
        std::vector<BoxInstance> boxes;
        if (finite_box(node.box) && !node.box.empty())
            boxes.push_back(node_box(node.box, faulty ? kFaultRed : node_box_colour(background)));
        for (size_t k = 0; k < node.child_boxes.size(); ++k)
            if (finite_box(node.child_boxes[k]) && !node.child_boxes[k].empty())
                boxes.push_back({node.child_boxes[k].lo, node.child_boxes[k].hi, kChildColours[k % kChildColours.size()]});
        if (!boxes_) boxes_ = std::make_unique<BoxBuffer>();
        boxes_->upload(boxes);
        std::vector<ColouredQuad> quads;
        if (node.axis >= 0 && finite_box(node.box) && std::isfinite(node.split))
            quads.push_back(split_plane_quad(node.box, node.axis, node.split));  // a KD node's plane across its cell
        if (!plane_) plane_ = std::make_unique<ColouredBuffer>();
        plane_->upload_quads(quads);
        uploaded_file_node_ = file_node_;
        uploaded_background_ = background;
        uploaded_trace_ = nullptr;  // the buffers no longer hold a step of our build
    }
    // The node's triangles in their child's colour, then the whole mesh dimmed (see draw_3d).
    for (size_t k = 0; k < node.triangles.size(); ++k)
        renderer.draw_mesh(*child_tris_[k], {.base_colour = node.leaf ? kLeafTriangles
                                                                      : rgb(kChildColours[k % kChildColours.size()])});
    renderer.draw_mesh(mesh, {.base_colour = kDimMesh});
    renderer.draw_quads(*plane_);
    renderer.draw_boxes(*boxes_);
}

}  // namespace accelviz
