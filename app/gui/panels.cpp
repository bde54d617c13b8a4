#include "app/gui/panels.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <cstdio>
#include <fstream>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "app/gui/camera_control.h"
#include "app/gui/session.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"

namespace accelviz {

namespace {

/// The built-in scene names (what builtin_scenes() lists; "cube" at least).
std::vector<BuiltinInfo> builtin_choices() {
    std::vector<BuiltinInfo> choices = builtin_scenes();
    if (choices.empty()) choices.push_back({"cube", "a cube"});
    return choices;
}

/// Grey explanatory text that wraps at the panel's edge.
void hint(const char* text) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    ImGui::TextWrapped("%s", text);
    ImGui::PopStyleColor();
}

/// A combo over `names` editing `value`; true when the user picked another one.
bool name_combo(const char* label, std::string& value, const std::vector<std::string>& names) {
    bool changed = false;
    if (ImGui::BeginCombo(label, value.c_str())) {
        for (const std::string& name : names)
            if (ImGui::Selectable(name.c_str(), name == value) && name != value) {
                value = name;
                changed = true;
            }
        ImGui::EndCombo();
    }
    return changed;
}

/// The same for an enum with to_string / parse functions.
template <class Enum, class Parse>
bool enum_combo(const char* label, Enum& value, const std::vector<std::string>& names, Parse parse) {
    std::string name(to_string(value));
    if (!name_combo(label, name, names)) return false;
    if (auto parsed = parse(name)) value = *parsed;
    return true;
}

/// A leaf-size slider over the BVH's whole range, 1..kBvhMaxLeafSize (the KD tree and
/// octree have no limit of their own; larger values come from the command line or a
/// preset). Logarithmic: the lecture's leaves of ~5 triangles stay easy to pick.
bool leaf_size_slider(const char* label, int& value) {
    ImGui::SliderInt(label, &value, 1, kBvhMaxLeafSize, "%d", ImGuiSliderFlags_Logarithmic);
    return ImGui::IsItemDeactivatedAfterEdit();
}

/// Widgets that apply on release (a rebuild per drag step would queue builds).
bool int_slider(const char* label, int& value, int lo, int hi, const char* format = "%d") {
    ImGui::SliderInt(label, &value, lo, hi, format, ImGuiSliderFlags_AlwaysClamp);
    return ImGui::IsItemDeactivatedAfterEdit();
}
bool float_slider(const char* label, float& value, float lo, float hi, const char* format = "%.2f",
                  ImGuiSliderFlags flags = 0) {
    ImGui::SliderFloat(label, &value, lo, hi, format, flags | ImGuiSliderFlags_AlwaysClamp);
    return ImGui::IsItemDeactivatedAfterEdit();
}

}  // namespace

// [SECTION] Scene

void ScenePanel::draw(AppState& state, Session& session, double dt) {
    if (!ImGui::CollapsingHeader("Scene", ImGuiTreeNodeFlags_DefaultOpen)) return;
    if (shown_source != state.scene) {  // the scene changed elsewhere (drop, preset): follow it
        source_text = state.scene;
        shown_source = state.scene;
    }

    // Built-in scenes: picking one loads it at once.
    const std::vector<BuiltinInfo> choices = builtin_choices();
    const bool is_builtin = state.scene.rfind("builtin:", 0) == 0;
    const std::string current = is_builtin ? state.scene.substr(8) : std::string();
    ImGui::SetNextItemWidth(-FLT_MIN);
    const std::string preview = is_builtin ? "Built-in: " + current : std::string("Built-in scenes");
    if (ImGui::BeginCombo("##builtin", preview.c_str())) {
        for (const BuiltinInfo& choice : choices) {
            const bool selected = is_builtin && current.rfind(choice.name, 0) == 0;
            if (ImGui::Selectable(choice.name.c_str(), selected)) session.open_scene(state, "builtin:" + choice.name);
            if (!choice.description.empty() && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", choice.description.c_str());
        }
        ImGui::EndCombo();
    }

    // Any source by text: an OBJ path or "builtin:NAME?k=v".
    const float button_width = ImGui::CalcTextSize("Open").x + 2 * ImGui::GetStyle().FramePadding.x;
    ImGui::SetNextItemWidth(-(button_width + ImGui::GetStyle().ItemSpacing.x));
    const bool entered = ImGui::InputTextWithHint("##source", "OBJ path or builtin:NAME", &source_text,
                                                  ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::SameLine();
    if ((ImGui::Button("Open") || entered) && !source_text.empty()) session.open_scene(state, source_text);
    hint("Or drop an .obj file on the window.");
    draw_timeline(state, session, dt);

    // The lecture's presets, in order (PageDown / PageUp step through them).
    const std::vector<PresetInfo>& presets = session.presets.entries();
    if (!presets.empty() && ImGui::TreeNodeEx("Presets", ImGuiTreeNodeFlags_DefaultOpen)) {
        for (size_t i = 0; i < presets.size(); ++i) {
            ImGui::PushID(int(i));
            if (ImGui::Selectable(presets[i].title.c_str(), int(i) == session.presets.current()))
                session.presets.load(int(i), state, session);
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", presets[i].path.c_str());
            ImGui::PopID();
        }
        hint("PageDown / PageUp: next / previous preset.");
        ImGui::TreePop();
    }

    if (session.loader.busy()) {
        ImGui::TextUnformatted((session.loader.activity() + " ...").c_str());
    }
}

/// A moving scene's time: a slider, Play, and whether a new time refits the BVH
/// (the same tree, boxes recomputed: cheap, but they stretch) or builds it anew.
void ScenePanel::draw_timeline(AppState& state, Session& session, double dt) {
    const std::optional<double> scene_t = scene_time(state.scene);
    if (!scene_t || !session.scene) {
        playing = false;
        return;
    }
    const bool waiting = session.loader.busy();
    if (!waiting && !ImGui::IsAnyItemActive()) time = float(*scene_t);
    ImGui::SetNextItemWidth(-(ImGui::CalcTextSize("Time t").x + ImGui::GetStyle().ItemInnerSpacing.x));
    bool changed = ImGui::SliderFloat("Time t", &time, 0.0f, 1.0f, "%.3f", ImGuiSliderFlags_AlwaysClamp) &&
                   ImGui::IsItemActive();
    if (ImGui::Button(playing ? "Pause##time" : "Play##time")) playing = !playing;
    ImGui::SameLine();
    const bool can_refit = state.accel.type == AccelType::Bvh && state.accel.bvh.width == 2;
    if (!can_refit) ImGui::BeginDisabled();
    // Ticked or unticked, the time on screen is loaded again the new way.
    if (ImGui::Checkbox("Refit the BVH", &state.refit_bvh)) changed = true;
    if (!can_refit) ImGui::EndDisabled();
    if (playing && !waiting && dt > 0) {  // one time at a time: the next once this one has arrived
        time = std::fmod(time + float(dt) * kPlaySpeed, 1.0f);
        changed = true;
    }
    if (changed) session.open_scene_at_time(state, time, state.refit_bvh && can_refit);
    hint(session.scene->refitted ? "The BVH is refitted: an earlier time's tree, its boxes stretched."
                                 : "Each time builds the structure anew.");
}

// [SECTION] Structure

namespace {

/// A structure from a file (a student's tree): which file, valid or not, its problems
/// one per line; "Build ours instead" goes back to building. True when it asks for a rebuild.
bool draw_structure_file(AccelConfig& a, const Session& session) {
    const size_t slash = a.structure_file.find_last_of('/');
    const std::string name = slash == std::string::npos ? a.structure_file : a.structure_file.substr(slash + 1);
    ImGui::TextWrapped("From file: %s", name.c_str());
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", a.structure_file.c_str());
    bool rebuild = false;
    if (ImGui::Button("Build ours instead")) {
        a.structure_file.clear();
        rebuild = true;
    }
    const LoadedScene* scene = session.scene.get();
    const CheckedStructureFile* file = scene && scene->accel_config.structure_file == a.structure_file
                                           ? scene->structure_file.get()
                                           : nullptr;
    if (!file) {
        hint("Reading and checking the file...");
        return rebuild;
    }
    const StructureCheck& check = file->check;
    if (check.valid()) {
        hint("Valid: our traversal runs through it (heat maps, stepper, Stats as for ours).");
        return rebuild;
    }
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.42f, 0.42f, 1.0f));
    ImGui::TextWrapped("NOT VALID: %llu problem%s. Red boxes: the nodes named. Rays go through brute force.",
                       (unsigned long long)check.problem_count, check.problem_count == 1 ? "" : "s");
    ImGui::PopStyleColor();
    // As tall as the first few problems wrapped (the rest scroll).
    const ImGuiStyle& style = ImGui::GetStyle();
    const float wrap = ImGui::GetContentRegionAvail().x - 2 * style.WindowPadding.x - style.ScrollbarSize;
    float height = 2 * style.WindowPadding.y;
    for (size_t i = 0; i < check.problems.size() && i < 4; ++i)
        height += ImGui::CalcTextSize(check.problems[i].message.c_str(), nullptr, false, wrap).y + style.ItemSpacing.y;
    if (ImGui::BeginChild("##problems", ImVec2(0, height), true)) {
        for (const StructureProblem& p : check.problems) ImGui::TextWrapped("%s", p.message.c_str());
        if (check.problem_count > check.problems.size())
            ImGui::TextDisabled("... and %llu more (accelviz check lists them all)",
                                (unsigned long long)(check.problem_count - check.problems.size()));
    }
    ImGui::EndChild();
    return rebuild;
}

}  // namespace

void StructurePanel::draw(AppState& state, Session& session) {
    if (!ImGui::CollapsingHeader("Structure", ImGuiTreeNodeFlags_DefaultOpen)) return;
    AccelConfig& a = state.accel;
    bool rebuild = false;
    if (!a.structure_file.empty()) {
        if (draw_structure_file(a, session)) session.rebuild_structure(state);
        draw_overlay_settings(state, session);
        return;
    }
    ImGui::PushItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
    // "###": the combo reads "Structure" like the section's header, but has its own ID.
    rebuild |= enum_combo("Structure###structure_type", a.type, accel_type_names(), parse_accel_type);
    if (a.type == AccelType::Bvh) {
        rebuild |= enum_combo("Build", a.bvh.builder, bvh_builder_names(), parse_bvh_builder);
        if (a.bvh.builder == BvhBuilder::SahBinned) rebuild |= int_slider("Bins (B)", a.bvh.bins, kBvhMinBins, kBvhMaxBins);
        rebuild |= leaf_size_slider("Max leaf size", a.bvh.max_leaf_size);
        if (a.bvh.builder == BvhBuilder::SahBinned || a.bvh.builder == BvhBuilder::SahSweep) {
            rebuild |= float_slider("C_trav", a.bvh.cost_trav, 0.0f, 10.0f);
            rebuild |= float_slider("C_isect", a.bvh.cost_isect, 0.1f, 10.0f);
        }
        rebuild |= enum_combo("Traversal", a.bvh_traversal, bvh_traversal_names(), parse_bvh_traversal);
        // The binary tree, or the same tree collapsed into nodes of 4 or 8 children whose
        // boxes are tested together (core/accel/wide_bvh.h).
        std::string width = std::to_string(a.bvh.width);
        if (name_combo("Children per node", width, {"2", "4", "8"})) {
            a.bvh.width = std::stoi(width);
            rebuild = true;
        }
    } else if (a.type == AccelType::Grid) {
        rebuild |= float_slider("Density C", a.grid.density, 0.5f, 100.0f, "%.1f", ImGuiSliderFlags_Logarithmic);
        rebuild |= enum_combo("Insert", a.grid.insert, grid_insert_names(), parse_grid_insert);
        rebuild |= ImGui::Checkbox("Mailbox", &a.grid.mailbox);
    } else if (a.type == AccelType::Kd) {
        rebuild |= enum_combo("Build", a.kd.builder, kd_builder_names(), parse_kd_builder);
        rebuild |= int_slider("Max depth", a.kd.max_depth, 0, kKdMaxDepth, a.kd.max_depth == 0 ? "auto" : "%d");
        rebuild |= leaf_size_slider("Leaf size", a.kd.leaf_size);
        if (a.kd.builder == KdBuilder::Sah) {
            rebuild |= float_slider("C_trav", a.kd.cost_trav, 0.0f, 10.0f);
            rebuild |= float_slider("C_isect", a.kd.cost_isect, 0.1f, 10.0f);
            rebuild |= float_slider("Empty bonus", a.kd.empty_bonus, 0.0f, 0.95f);
        }
        rebuild |= ImGui::Checkbox("Hit must be in cell", &a.kd.strict_cell);
        rebuild |= ImGui::Checkbox("Mailbox", &a.kd.mailbox);
    } else if (a.type == AccelType::Octree) {
        rebuild |= int_slider("Max depth", a.octree.max_depth, 1, kOctreeMaxDepth);
        rebuild |= leaf_size_slider("Leaf size", a.octree.leaf_size);
        rebuild |= ImGui::Checkbox("Mailbox", &a.octree.mailbox);
    } else if (a.type == AccelType::Bsp) {
        rebuild |= int_slider("Max depth", a.bsp.max_depth, 1, kBspMaxDepth);
        rebuild |= leaf_size_slider("Leaf size", a.bsp.leaf_size);
        rebuild |= int_slider("Planes tried", a.bsp.candidates, 1, 64);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("How many of a node's triangles offer their plane. They compete with\n"
                              "axis-aligned planes under the SAH; the cheapest splits the node.");
        rebuild |= ImGui::Checkbox("Mailbox", &a.bsp.mailbox);
    }
    // Every structure: Möller–Trumbore (the lecture's) or the watertight test.
    rebuild |= enum_combo("Triangle test", a.triangle_test, triangle_test_names(), parse_triangle_test);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("mt: Moller-Trumbore, the lecture's barycentric solve.\n"
                          "watertight: Woop, Benthin & Wald 2013; no ray slips between two triangles.");
    ImGui::PopItemWidth();
    // Or a structure from a file (docs/structure-format.md): a student's tree, checked.
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
    const bool entered = ImGui::InputTextWithHint("##structure_file", "tree.json", &file_text,
                                                  ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::SameLine();
    if ((ImGui::Button("From file") || entered) && !file_text.empty()) {
        session.use_structure_file(state, file_text);
        return;
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Load a structure from a file (a student's BVH, KD tree or grid; docs/structure-format.md)\n"
                          "instead of building one. Dropping the file on the window does the same.");
    if (rebuild) session.rebuild_structure(state);
    draw_overlay_settings(state, session);
}

void StructurePanel::draw_overlay_settings(AppState& state, const Session& session) {
    const AccelConfig& a = state.accel;
    // What of it the 3D view shows.
    OverlaySettings& o = state.overlay;
    ImGui::Checkbox("Show structure", &o.show_structure);
    const int deepest = session.overlay.deepest_level;
    if (deepest > 0) {
        ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
        int lo = std::min(o.level_min, deepest), hi = std::min(o.level_max, deepest);
        if (ImGui::DragIntRange2("Levels", &lo, &hi, 0.1f, 0, deepest, "%d", "%d", ImGuiSliderFlags_AlwaysClamp)) {
            o.level_min = lo;
            o.level_max = hi == deepest ? 64 : hi;  // "to the bottom" stays so for a deeper rebuild
        }
        if (ImGui::SmallButton("All levels")) {
            o.level_min = 0;
            o.level_max = 64;
        }
        ImGui::SameLine();
        if (ImGui::SmallButton("Level -")) o.level_min = o.level_max = std::max(0, std::min(o.level_min, deepest) - 1);
        ImGui::SameLine();
        if (ImGui::SmallButton("Level +")) o.level_min = o.level_max = std::min(deepest, std::min(o.level_min, deepest) + 1);
    }
    if (a.type != AccelType::Grid && a.type != AccelType::Naive) ImGui::Checkbox("Leaves only", &o.leaves_only);
    {
        // The box budget in thousands (0: no limit).
        int thousands = int(o.max_boxes / 1000);
        ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
        ImGui::SliderInt("Box budget", &thousands, 0, 2000, thousands == 0 ? "no limit" : "%dk",
                         ImGuiSliderFlags_Logarithmic);
        if (ImGui::IsItemDeactivatedAfterEdit()) o.max_boxes = size_t(thousands) * 1000;
    }
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
    ImGui::SliderFloat("Mesh opacity", &o.mesh_opacity, 0.0f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp);
}

// [SECTION] Stats

namespace {

/// The histogram as bars: leaves / cells holding 1, 2, ... triangles (at most
/// 32 bars; wider bins for larger counts). Empty ones are a number, not a bar:
/// in a grid or KD tree they would dwarf the rest.
void draw_histogram(const LeafHistogram& h) {
    if (h.counts.size() < 2 && (h.counts.empty() || h.counts[0] == 0)) return;
    const size_t most = h.counts.size() - 1;  // the fullest leaf / cell
    const size_t bin = most <= 32 ? 1 : (most + 31) / 32;
    std::vector<float> bars((most + bin - 1) / bin, 0.0f);
    double sum = 0;
    for (size_t k = 1; k <= most; ++k) {
        bars[(k - 1) / bin] += float(h.counts[k]);
        sum += double(k) * double(h.counts[k]);
    }
    const uint64_t total = h.total(), empty = h.counts.empty() ? 0 : h.counts[0];
    char text[160];
    std::snprintf(text, sizeof text, "%s by triangle count: %llu (%llu empty), mean %.1f, max %zu", h.what.c_str(),
                  (unsigned long long)total, (unsigned long long)empty, total > empty ? sum / double(total - empty) : 0.0,
                  most);
    ImGui::TextWrapped("%s", text);
    if (bars.empty()) return;
    ImGui::PlotHistogram("##leaf_histogram", bars.data(), int(bars.size()), 0, nullptr, 0.0f, FLT_MAX,
                         ImVec2(ImGui::GetContentRegionAvail().x, 5.0f * ImGui::GetFontSize()));
    // The x axis: first and last bin.
    char left[32], right[48];
    std::snprintf(left, sizeof left, "1");
    if (bin == 1)
        std::snprintf(right, sizeof right, "%zu triangles", most);
    else
        std::snprintf(right, sizeof right, "%zu (bars of %zu)", most, bin);
    ImGui::TextDisabled("%s", left);
    ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - ImGui::CalcTextSize(right).x);
    ImGui::TextDisabled("%s", right);
}

}  // namespace

void StatsPanel::draw(const AppState&, const Session& session) {
    if (open_at_start) ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (!ImGui::CollapsingHeader("Stats")) return;
    const LoadedScene* scene = session.scene.get();
    if (!scene) return;
    if (!session.overlay.legend.empty()) {
        hint(session.overlay.legend.c_str());
    }
    if (scene->degenerate_note) hint(scene->degenerate_note->c_str());
    const bool same = !histogram_of.expired() && !histogram_of.owner_before(scene->accel) &&
                      !scene->accel.owner_before(histogram_of);
    if (!same) {  // a new structure: count its leaves once
        histogram = leaf_histogram(*scene->accel);
        histogram_of = scene->accel;
    }
    draw_histogram(histogram);
    if (const CheckedStructureFile* file = scene->structure_file.get()) {
        // A structure from a file: its own shape (our build statistics do not apply).
        if (!file->check.valid()) return;
        const bool same_file = !figures_of.expired() && !figures_of.owner_before(scene->structure_file) &&
                               !scene->structure_file.owner_before(figures_of);
        if (!same_file) {
            figures = measure_structure(*file->file, *scene->mesh, *scene->accel, {}, *scene->accel, {});
            figures_of = scene->structure_file;
        }
        if (!ImGui::BeginTable("file_stats", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp)) return;
        auto row = [](const char* key, const std::string& value) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(key);
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(value.c_str());
        };
        char number[32];
        std::snprintf(number, sizeof number, "%.4g", figures.sah_cost);
        row("SAH cost (C_trav = C_isect = 1)", number);
        row("nodes", std::to_string(figures.nodes));
        row("leaves", std::to_string(figures.leaves));
        row("depth", std::to_string(figures.depth));
        std::snprintf(number, sizeof number, "%.2f", file->file->type == AccelType::Bvh ? figures.avg_children
                                                                                       : figures.references);
        row(file->file->type == AccelType::Bvh ? "children per node" : "references per triangle", number);
        if (!file->file->builder.empty()) row("built by", file->file->builder);
        ImGui::EndTable();
        return;
    }
    const nlohmann::json stats = scene->accel->stats();
    if (!ImGui::BeginTable("stats", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp)) return;
    for (const auto& [key, value] : stats.items()) {
        if (key.ends_with("_ms")) continue;  // not deterministic; the status line has the build time
        std::string text;
        if (value.is_object() && value.contains("nodes") && value.contains("max_depth")) {
            // A structure it was made from (the wide BVH's binary tree), in one line.
            char line[128];
            std::snprintf(line, sizeof line, "%s nodes, depth %s, SAH cost %.4g", value["nodes"].dump().c_str(),
                          value["max_depth"].dump().c_str(), value.value("sah_cost", 0.0));
            text = line;
        } else if (value.is_number_float()) {
            char number[32];
            std::snprintf(number, sizeof number, "%.4g", value.get<double>());
            text = number;
        } else if (value.is_string()) {
            text = value.get<std::string>();
        } else if (value.is_array() && !value.empty() && value[0].is_string()) {
            for (const auto& line : value) text += line.get<std::string>() + "\n";
        } else {
            text = value.dump();
        }
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(key.c_str());
        ImGui::TableNextColumn();
        ImGui::TextWrapped("%s", text.c_str());
    }
    ImGui::EndTable();
}

// [SECTION] View

void ViewPanel::draw(AppState& state, Session& session, double view_aspect) {
    if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
    draw_scale(state.view);
    draw_colours(state.view);
    ImGui::Checkbox("Scene bounds", &state.view.show_bounds);
    draw_split_choices(state.view);
    ImGui::Separator();
    draw_light(state, session);
    ImGui::Separator();
    draw_slice(state, session);
    ImGui::Separator();
    draw_camera(state, session, view_aspect);
    ImGui::Separator();
    draw_files(state, session);
}

void ViewPanel::draw_scale(ViewSettings& view) {
    // UI scale: the font is rebuilt at the new size, so apply it on release only.
    if (!editing_scale) ui_scale_edit = view.ui_scale;
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
    char label[32];
    std::snprintf(label, sizeof label, "%.2f (%d px)", ui_scale_edit, font_pixels(ui_scale_edit));
    ImGui::SliderFloat("UI scale", &ui_scale_edit, 0.75f, 3.0f, label);
    editing_scale = ImGui::IsItemActive();
    if (ImGui::IsItemDeactivatedAfterEdit()) view.ui_scale = ui_scale_edit;
    if (ImGui::Button("Desk 1x")) {
        view.ui_scale = 1.0f;
        view.line_width = 1.0f;
    }
    ImGui::SameLine();
    if (ImGui::Button("Projector 2x")) {
        view.ui_scale = 2.0f;
        view.line_width = 2.0f;
    }
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
    ImGui::SliderFloat("Line width", &view.line_width, 1.0f, 6.0f, "%.1f px", ImGuiSliderFlags_AlwaysClamp);
}

void ViewPanel::draw_colours(ViewSettings& view) {
    if (ImGui::Checkbox("Light theme", &view.light_theme)) {
        // Follow the theme with the background while it is still one of the defaults.
        const Rgb light_background{236, 236, 232};
        if (view.light_theme && view.background == kBackground) view.background = light_background;
        if (!view.light_theme && view.background == light_background) view.background = kBackground;
    }
    // Background: a few swatches that read well on a projector, and a picker.
    ImGui::TextUnformatted("Background");
    static constexpr Rgb kSwatches[] = {kBackground, {0, 0, 0}, {128, 128, 128}, {236, 236, 232}, {255, 255, 255}};
    const float swatch = ImGui::GetFrameHeight();
    ImGui::PushStyleVar(ImGuiStyleVar_FrameBorderSize, 1.0f);  // a dark swatch on a dark panel stays visible
    for (const Rgb& colour : kSwatches) {
        if (&colour != &kSwatches[0]) ImGui::SameLine();
        ImGui::PushID(&colour);
        const ImVec4 c(colour.r / 255.0f, colour.g / 255.0f, colour.b / 255.0f, 1.0f);
        if (ImGui::ColorButton("##swatch", c, ImGuiColorEditFlags_NoTooltip, ImVec2(swatch, swatch)))
            view.background = colour;
        ImGui::PopID();
    }
    ImGui::SameLine();
    float background[3] = {view.background.r / 255.0f, view.background.g / 255.0f, view.background.b / 255.0f};
    if (ImGui::ColorEdit3("##background", background, ImGuiColorEditFlags_NoInputs))
        view.background = {uint8_t(background[0] * 255.0f + 0.5f), uint8_t(background[1] * 255.0f + 0.5f),
                           uint8_t(background[2] * 255.0f + 0.5f)};
    ImGui::PopStyleVar();
}

void ViewPanel::draw_split_choices(ViewSettings& view) {
    // Raster vs ray cast (S).
    bool split = view.mode == ViewMode::Split;
    if (ImGui::Checkbox("Raster | ray cast (S)", &split)) view.mode = split ? ViewMode::Split : ViewMode::View3D;
    if (!split) {
        // How the 3D view draws the mesh: the lecture's last slide, on screen.
        static constexpr const char* kDrawLabels[] = {"raster (OpenGL)", "ray cast (CPU)", "auto (the faster)"};
        static_assert(std::size(kDrawLabels) == kDrawWithNames.entries.size());
        int draw_with = int(view.draw_with);  // the labels are in the enum's order
        ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
        if (ImGui::Combo("Draw with", &draw_with, kDrawLabels, int(std::size(kDrawLabels))))
            view.draw_with = DrawWith(draw_with);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("Raster: OpenGL draws every triangle (z-buffer).\n"
                              "Ray cast: a ray per pixel through the structure, on the CPU;\n"
                              "a quarter of the pixels while the camera moves.\n"
                              "Auto: whichever was measured faster on this scene\n(raster where brute force answers the rays).");
    } else {
        static constexpr const char* kLeftLabels[] = {"OpenGL (its z-buffer)", "CPU rasterizer", "CPU raster depth", "OpenGL depth (read back)"};
        static_assert(std::size(kLeftLabels) == kLeftViewNames.entries.size());
        int left = int(view.left_view);  // the labels are in the enum's order
        ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
        if (ImGui::Combo("Raster shows", &left, kLeftLabels, int(std::size(kLeftLabels))))
            view.left_view = LeftView(left);
        static constexpr const char* kLabels[] = {"shaded", "heat: nodes visited", "heat: triangle tests", "depth",
                                                  "depth difference", "heat: stack depth (GPU)"};
        static_assert(std::size(kLabels) == kRightViewNames.entries.size());
        int current = int(view.right_view);  // the labels are in the enum's order
        ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
        if (ImGui::Combo("Ray cast shows", &current, kLabels, int(std::size(kLabels)))) view.right_view = RightView(current);
        // Who casts the right half: the CPU, or the GPU's compute shader (the binary BVH).
        int by = int(view.ray_cast_by);
        ImGui::TextUnformatted("Ray cast by");
        ImGui::SameLine();
        ImGui::RadioButton("CPU##cast_by", &by, int(RayCastBy::Cpu));
        ImGui::SameLine();
        ImGui::RadioButton("GPU##cast_by", &by, int(RayCastBy::Gpu));
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("The binary BVH traversed by an OpenGL 4.3 compute shader, one invocation per\n"
                              "pixel (algorithm 2, a stack each) with the CPU's arithmetic: the same triangles at\n"
                              "the same t (bit for bit on llvmpipe).\n"
                              "Heat maps then show each invocation's loop iterations, tests or stack depth.\n"
                              "Cast on this thread once the camera stops (llvmpipe has no GPU: it is slow).");
        view.ray_cast_by = RayCastBy(by);
        ImGui::Checkbox("Heat: same scale for all structures", &view.heat_same_scale);
        if (is_heat(view.right_view)) {
            static constexpr const char* kRaysLabels[] = {"camera rays", "shadow rays", "reflection rays"};
            static_assert(std::size(kRaysLabels) == kHeatRaysNames.entries.size());
            int rays = int(view.heat_rays);  // the labels are in the enum's order
            ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
            if (ImGui::Combo("Heat of", &rays, kRaysLabels, int(std::size(kRaysLabels)))) view.heat_rays = HeatRays(rays);
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("Whose work per pixel: the camera's rays, or the light's shadow or\n"
                                  "reflection rays (Light: Shadows, Reflections).");
        }
        draw_fill_order(view);
    }
}

void ViewPanel::draw_slice(AppState& state, const Session& session) {
    ViewSettings& view = state.view;
    // Switched on, the mesh turns translucent (once): the cross-section lies inside it.
    if (ImGui::Checkbox("Inside / outside slice", &view.slice) && view.slice && state.overlay.mesh_opacity >= 1.0f)
        state.overlay.mesh_opacity = 0.35f;
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("A plane across the scene, each of its points coloured by ray parity: three rays\n"
                          "from the point count the surfaces they cross (odd: inside) and vote.\n"
                          "Orange: inside (3 of 3), dark blue: outside; lighter shades: the rays disagree.");
    if (!view.slice) return;
    ImGui::SameLine();
    for (int axis = 0; axis < 3; ++axis) {
        const char* names[3] = {"x##slice", "y##slice", "z##slice"};
        if (axis > 0) ImGui::SameLine();
        ImGui::RadioButton(names[axis], &view.slice_axis, axis);
    }
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
    ImGui::SliderFloat("Slice at", &view.slice_at, 0.0f, 1.0f, "%.2f of the box", ImGuiSliderFlags_AlwaysClamp);
    if (!session.slice.status().empty()) hint(session.slice.status().c_str());
}

void ViewPanel::draw_light(AppState& state, const Session& session) {
    // The lecture's last slide: which lights a point sees (shadow rays), what a surface reflects.
    LightSettings& light = state.light;
    ImGui::TextUnformatted("Light (ray cast)");
    ImGui::Checkbox("Shadows", &light.shadows);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("A shadow ray from every hit to the light: the any-hit query,\n"
                          "which stops at the first triangle in the way.");
    ImGui::SameLine();
    ImGui::Checkbox("Reflections", &light.reflections);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("One reflection ray (closest hit) from every mirror triangle.\n"
                          "builtin:cornell-mirror's tall block is a mirror.");
    const LoadedScene* scene = session.scene.get();
    if (light.reflections && scene && scene->mesh->mirror.empty())
        ImGui::TextWrapped("This scene has no mirrors (builtin:cornell-mirror has).");
    if (!scene) return;
    // The light's position: dragged here or by its marker in the 3D view.
    const Vec3d at = light_position(light, scene->bounds);
    float position[3] = {float(at.x), float(at.y), float(at.z)};
    const Vec3 extent = scene->bounds.hi - scene->bounds.lo;
    const float speed = std::max({extent.x, extent.y, extent.z, 1e-30f}) * 0.005f;
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
    if (ImGui::DragFloat3("Light at", position, speed, 0.0f, 0.0f, "%.3g")) {
        Vec3d moved{position[0], position[1], position[2]};
        if (within_max_coordinate(moved)) light.position = moved;
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Drag a number, or drag the sun in the 3D view.");
    if (light.position) {
        ImGui::SameLine();
        if (ImGui::Button("Reset##light")) light.position.reset();
    }
    if (!light.point_light()) {
        ImGui::TextDisabled("now a headlight (a light at the eye)");
    } else {
        if (ImGui::Button("Headlight")) light = LightSettings{};
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("Back to a light at the eye: no shadows, no reflections.");
        ImGui::SameLine();
        ImGui::TextDisabled("the mesh is ray cast");
    }
}

void ViewPanel::draw_fill_order(ViewSettings& view) {
    if (ImGui::Checkbox("Fill order (both loops part-way)", &view.fill_order) && view.fill_order) {
        view.fill = 0.0f;  // from the start: press Play
        fill_playing = false;
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Left: the CPU rasterizer, triangle after triangle (its z-buffer filling in).\n"
                          "Right: the ray caster, pixel after pixel. Both stopped at the same share of their work.");
    if (!view.fill_order) {
        fill_playing = false;
        return;
    }
    float percent = view.fill * 100.0f;
    if (ImGui::SliderFloat("Done", &percent, 0.0f, 100.0f, "%.1f %%", ImGuiSliderFlags_AlwaysClamp)) {
        view.fill = percent / 100.0f;
        fill_playing = false;
    }
    if (ImGui::Button(fill_playing ? "Pause##fill" : "Play##fill")) play_or_pause_fill(view);
    ImGui::SameLine();
    // Whole percents, so that repeated steps land on 0 and 100 exactly.
    auto step_percent = [&](float delta) {
        view.fill = std::clamp(std::round(view.fill * 100.0f + delta) / 100.0f, 0.0f, 1.0f);
        fill_playing = false;
    };
    if (ImGui::Button("-1%##fill")) step_percent(-1.0f);
    ImGui::SameLine();
    if (ImGui::Button("+1%##fill")) step_percent(+1.0f);
    float speed = fill_speed * 100.0f;
    if (ImGui::SliderFloat("Speed", &speed, 1.0f, 100.0f, "%.0f %%/s", ImGuiSliderFlags_Logarithmic))
        fill_speed = speed / 100.0f;
}

void ViewPanel::play_or_pause_fill(ViewSettings& view) {
    if (!fill_playing && view.fill >= 1.0f) view.fill = 0.0f;  // play again from the start
    fill_playing = !fill_playing;
}

void ViewPanel::advance_fill(ViewSettings& view, double seconds, bool split) {
    if (!split || !view.fill_order) fill_playing = false;
    if (!fill_playing) return;
    view.fill = std::min(1.0f, view.fill + float(seconds) * fill_speed);
    if (view.fill >= 1.0f) fill_playing = false;
}

void ViewPanel::draw_camera(AppState& state, const Session& session, double view_aspect) {
    if (state.camera) {
        float fov = float(state.camera->fov_deg);
        ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
        if (ImGui::SliderFloat("Field of view", &fov, 10.0f, 120.0f, "%.0f deg")) state.camera->fov_deg = fov;
    }
    const bool have_scene = session.scene != nullptr;
    if (ImGui::Button("Frame scene (F)") && have_scene && state.camera)
        frame_bounds(*state.camera, session.scene->bounds, view_aspect);
    ImGui::SameLine();
    if (ImGui::Button("Reset view (R)") && have_scene) {
        state.camera = default_camera(session.scene->bounds);
        frame_bounds(*state.camera, session.scene->bounds, view_aspect);
    }
    if (ImGui::Button(copied ? "Copied to clipboard###copy_camera" : "Copy camera as CLI flags###copy_camera") &&
        state.camera) {
        ImGui::SetClipboardText(camera_cli_flags(*state.camera).c_str());
        copied = true;
    }
    if (copied && !ImGui::IsItemHovered()) copied = false;
}

void ViewPanel::draw_files(AppState& state, Session& session) {
    // The whole state as JSON (a preset is such a file), and screenshots.
    const float button = ImGui::CalcTextSize("Save").x + ImGui::CalcTextSize("Load").x +
                         4 * ImGui::GetStyle().FramePadding.x + 2 * ImGui::GetStyle().ItemSpacing.x;
    ImGui::SetNextItemWidth(-button);
    ImGui::InputText("##state_path", &state_path);
    ImGui::SameLine();
    if (ImGui::Button("Save")) {
        std::ofstream out(state_path);
        out << to_json(state).dump(2) << "\n";
        session.notify(out ? "State saved: " + state_path : state_path + ": cannot write", !out);
    }
    ImGui::SameLine();
    if (ImGui::Button("Load")) {
        if (auto loaded = load_app_state_file_checked(state_path); !loaded) {
            session.notify(loaded.error(), true);
        } else {
            session.apply_state(state, *loaded);
        }
    }
    const float shot_button = ImGui::CalcTextSize("Screenshot").x + 2 * ImGui::GetStyle().FramePadding.x +
                              ImGui::GetStyle().ItemSpacing.x;
    ImGui::SetNextItemWidth(-shot_button);
    ImGui::InputText("##screenshot_path", &screenshot_path);
    ImGui::SameLine();
    if (ImGui::Button("Screenshot")) session.screenshot_path = screenshot_path;
}

// [SECTION] Status line

namespace {

/// What drew the mesh of the last frame, for the status line.
std::string drawn_by(const AppState& state, const Session& session, bool deterministic) {
    // "auto:" when auto chose (a point light needs rays whatever Draw with says).
    std::string text = state.view.draw_with == DrawWith::Auto && !state.light.point_light() ? "auto: " : "";
    if (!session.mesh_ray_cast) {
        text += "raster (OpenGL)";
        if (session.brute_force_cast_refused) text += ", a brute-force ray cast of this view would take minutes";
        return text;
    }
    text += "ray cast (CPU)";
    if (state.light.shadows) text += ", shadows";
    if (state.light.reflections) text += ", reflections";
    const auto& shown = session.surface_cast.shown();
    if (!shown || shown->scene != session.scene_generation) return text + ", casting ...";
    if (shown->divisor > 1) text += ", a quarter of the pixels";
    if (!deterministic) {
        char ms[48];
        std::snprintf(ms, sizeof ms, ", %.0f ms", session.surface_cast.shown_milliseconds());
        text += ms;
    }
    return text;
}

}  // namespace

void StatsBar::draw(const AppState& state, const Session& session, double frame_ms, bool deterministic) {
    std::string line;
    if (const LoadedScene* scene = session.scene.get()) {
        char text[256];
        std::snprintf(text, sizeof text, "%s  |  %zu triangles  |  structure: %s", state.scene.c_str(),
                      scene->mesh->triangle_count(), std::string(to_string(scene->accel_config.type)).c_str());
        line = text;
        if (const CheckedStructureFile* file = scene->structure_file.get())
            line += file->check.valid() ? " from a file" : " from a file, NOT VALID (rays: brute force)";
        // The steppers draw their own boxes in place of the whole structure's.
        const bool stepper_3d = (state.stepper.open && state.stepper.ray) || session.build_stepper.shows_3d(state);
        if (state.overlay.show_structure && !session.overlay.boxes.empty() && !stepper_3d) {
            const size_t drawn = session.overlay.moving_prefix(session.moving_boxes.boxes());
            if (session.camera_moving && drawn < session.overlay.boxes.size())
                std::snprintf(text, sizeof text, ", %zu of %zu boxes shown while moving", drawn,
                              session.overlay.boxes.size());
            else
                std::snprintf(text, sizeof text, ", %zu boxes shown", session.overlay.boxes.size());
            line += text;
        }
        if (!deterministic) {
            std::snprintf(text, sizeof text, " (load %.0f ms, %s %.0f ms)", scene->load_seconds * 1e3,
                          scene->refitted ? "refit" : "build", scene->build_seconds * 1e3);
            line += text;
        }
    } else {
        line = "no scene";
    }
    // How the mesh was drawn, unless rasterized as by default (auto on a small mesh).
    if (session.scene && state.view.mode == ViewMode::View3D &&
        (state.view.draw_with == DrawWith::RayCast || state.light.point_light() || session.mesh_ray_cast ||
         session.brute_force_cast_refused))
        line += "  |  " + drawn_by(state, session, deterministic);
    if (!deterministic && frame_ms > 0) {
        char text[64];
        std::snprintf(text, sizeof text, "  |  %.1f ms/frame", frame_ms);
        line += text;
    }
    if (session.loader.busy()) line += "  |  " + session.loader.activity() + " ...";
    if (const std::string caption = session.presets.caption(); !caption.empty()) line = caption + "  |  " + line;
    ImGui::TextUnformatted(line.c_str());
    last_line = line;
    // The hint at the right end, where the line leaves room for it (never over it).
    const float hint_x = ImGui::GetWindowContentRegionMax().x - ImGui::CalcTextSize("F1: help").x;
    if (ImGui::GetItemRectMax().x + ImGui::GetFontSize() < hint_x + ImGui::GetWindowPos().x) {
        ImGui::SameLine(hint_x);
        ImGui::TextDisabled("F1: help");
    }
}

// [SECTION] Help

void HelpWindow::draw(AppState& state) {
    if (!state.view.show_help) return;
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(viewport->GetCenter(), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                                   ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                                   ImGuiWindowFlags_NoMove;
    if (ImGui::Begin("Keyboard and mouse (F1)", &state.view.show_help, flags)) {
        static constexpr const char* kShortcuts[][2] = {
            {"Left drag", "orbit around the target"},
            {"Right or middle drag, Shift + left drag", "pan"},
            {"Mouse wheel", "zoom (move towards the target)"},
            {"Arrow keys", "orbit (a stepper takes Left / Right)"},
            {"Shift + arrow keys", "pan"},
            {"+ / -", "zoom in / out"},
            {"F", "frame the scene"},
            {"R", "reset to the default view"},
            {"S", "raster | ray cast side by side"},
            {"PageDown / PageUp", "next / previous preset (assets/presets)"},
            {"Tab", "hide / show the panels"},
            {"Click (ray stepper open)", "step the ray of that pixel"},
            {"Left drag on the sun / on q", "move the light / the nearest-point query"},
            {"Right / Left, Home / End (a stepper open)", "next / previous, first / last step"},
            {"Space (ray or nearest-point stepper open)", "play / pause"},
            {"Space (split view's fill order, no ray stepper)", "play / pause both loops"},
            {"F1", "this help"},
            {"Esc", "close this help; cancel a load or build"},
            {"L", "lecture mode: full screen, no sidebar"},
            {"C, B (lecture mode)", "hide the caption bar, blank the screen"},
            {"Home / End (lecture mode, no stepper)", "first / last preset"},
            {"F12", "screenshot (the View panel's file)"},
            {"Drop an .obj file", "open it"},
        };
        if (ImGui::BeginTable("shortcuts", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit)) {
            for (const auto& row : kShortcuts) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(row[0]);
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(row[1]);
            }
            ImGui::EndTable();
        }
    }
    ImGui::End();
}

}  // namespace accelviz
