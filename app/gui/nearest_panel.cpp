#include "app/gui/nearest_panel.h"

#include <algorithm>
#include <cmath>

#include <imgui.h>

#include "app/gui/session.h"

namespace accelviz {

namespace {

ImVec4 im_vec4(DebugColour c) { return ImVec4(c.r / 255.0f, c.g / 255.0f, c.b / 255.0f, 1.0f); }

void grey_text(const char* text) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    ImGui::TextWrapped("%s", text);
    ImGui::PopStyleColor();
}

/// A coloured square and its meaning, for the legend.
void legend_entry(DebugColour c, const char* meaning) {
    ImGui::ColorButton(meaning, im_vec4(c), ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoDragDrop,
                       ImVec2(ImGui::GetFontSize() * 0.8f, ImGui::GetFontSize() * 0.8f));
    ImGui::SameLine();
    ImGui::TextUnformatted(meaning);
}

}  // namespace

void NearestPanel::update(AppState& state, Session& session, double delta_seconds, bool wait) {
    if (!state.nearest.open || !session.scene) {
        // Closed: the recording goes, and with it the scene it held.
        searched_scene.reset();
        searched_point.reset();
        search.reset();
        return;
    }
    if (!state.nearest.point) state.nearest.point = default_query_point(session.scene->bounds);
    const Vec3d q = *state.nearest.point;
    const bool new_scene = searched_scene != session.scene;
    if (new_scene || !searched_point || *searched_point != q) {
        if (new_scene) boxes = NodeBoxes(*session.scene->accel);
        searched_scene = session.scene;
        searched_point = q;
        search.reset();
        error.clear();
        const Accelerator& accel = *session.scene->accel;
        if (accel.type() == AccelType::Naive && session.scene->mesh->triangle_count() > kNearestNaiveMaxTriangles) {
            error = "naive measures every triangle: too many events to step on this mesh. Choose the BVH or the "
                    "KD tree in Structure.";
        } else if (auto recorded = record_nearest(accel, *session.scene->mesh, q)) {
            search = std::move(*recorded);
        } else {
            error = recorded.error() + ". Choose naive, the BVH (width 2) or the KD tree in Structure.";
        }
        shown_step = size_t(-1);
        playback.restart();
        for (int a = 0; a < 3; ++a) point_edit[a] = float(a == 0 ? q.x : a == 1 ? q.y : q.z);
    }
    const size_t end = search ? search->events.size() : 0;
    if (search) state.nearest.step = std::min(state.nearest.step, end);  // past the end (a drag): the final state
    if (!wait) playback.advance(state.nearest.step, end, delta_seconds);
    const size_t step = std::min(state.nearest.step, end);
    if (step != shown_step) {
        shown_step = step;
        step_state = search ? replay(search->events, step) : StepState{};
        geometry = search ? nearest_geometry(*search, step_state, boxes, *session.scene->mesh) : DebugGeometry{};
        geometry_dirty = true;
    }
}

void NearestPanel::handle_keys(AppState& state) {
    if (state.nearest.open && search) playback.handle_keys(state.nearest.step, search->events.size());
}

void NearestPanel::draw(AppState& state, Session& session, bool lecture) {
    const std::string structure = session.scene ? std::string(to_string(session.scene->accel_config.type)) : "?";
    const std::string title = "Nearest point: " + structure;
    const float close_width = ImGui::CalcTextSize("Close").x + 2.0f * ImGui::GetStyle().FramePadding.x;
    ImGui::TextUnformatted(title.c_str());
    ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - close_width);
    if (ImGui::SmallButton("Close")) {
        state.nearest.open = false;
        playback.playing = false;
    }
    if (!lecture)
        grey_text("The point of the mesh nearest to q. A box is visited nearest first and skipped when it lies "
                  "wholly outside the sphere of the best distance so far, which shrinks as nearer triangles are "
                  "found. Drag q in the 3D view, or type it.");
    ImGui::SetNextItemWidth(-FLT_MIN);
    if (ImGui::InputFloat3("##q", point_edit, "%.4g", ImGuiInputTextFlags_EnterReturnsTrue)) {
        const Vec3d typed{point_edit[0], point_edit[1], point_edit[2]};
        if (within_max_coordinate(typed)) {
            state.nearest.point = typed;
            state.nearest.step = 0;
        }
    }
    if (!search) {
        ImGui::PushStyleColor(ImGuiCol_Text, im_vec4(kStepColours.tested_miss));
        ImGui::TextWrapped("%s", error.empty() ? "no scene yet" : error.c_str());
        ImGui::PopStyleColor();
        return;
    }
    const size_t end = search->events.size();
    playback.draw_buttons(state.nearest.step, end);
    const size_t step = std::min(state.nearest.step, end);
    ImGui::Text("step %zu of %zu", step, end);
    if (step > 0) {
        ImGui::PushStyleColor(ImGuiCol_Text, im_vec4(kStepColours.interval));
        ImGui::TextWrapped("%s", explain_nearest_event(search->events[step - 1], step_state).c_str());
        ImGui::PopStyleColor();
    } else {
        grey_text("before the first event: press Right (or >) to step");
    }
    playback.draw_event_list(search->events, state.nearest.step, lecture ? 3 : 7,
                             describe_nearest_event);

    // Where the search stands: the best so far and the work against naive's.
    const Counters& c = step_state.counters;
    size_t skipped = step_state.culled.size();
    const size_t triangles = session.scene ? session.scene->mesh->triangle_count() : 0;
    if (step_state.closest.found())
        ImGui::TextColored(im_vec4(kStepColours.closest), "best so far: triangle %u, distance %.6g",
                           step_state.closest.tri, step_state.closest.t);
    else
        ImGui::TextDisabled("best so far: none (the sphere is infinite)");
    ImGui::Text("visited %llu   skipped %zu   waiting %zu", (unsigned long long)c.nodes_visited, skipped,
                step_state.stack.size());
    ImGui::Text("triangles measured %llu of naive %zu", (unsigned long long)c.triangle_tests, triangles);
    if (step_state.done && search->result.found())
        ImGui::TextWrapped("nearest point (%.5g, %.5g, %.5g)", search->result.point.x, search->result.point.y,
                           search->result.point.z);

    if (ImGui::TreeNodeEx("Colours", lecture ? 0 : ImGuiTreeNodeFlags_DefaultOpen)) {
        legend_entry(kStepColours.query, "q, the query point");
        legend_entry(kStepColours.closest, "best so far: its sphere and point");
        legend_entry(kStepColours.current, "the node being worked on");
        legend_entry(kStepColours.stacked, "waiting on the stack");
        legend_entry(kStepColours.culled_missed, "skipped: outside the sphere");
        legend_entry(kStepColours.visited, "visited earlier");
        legend_entry(kStepColours.triangle_hit, "measured: nearer than all before");
        legend_entry(kStepColours.triangle_miss, "measured: not nearer");
        ImGui::TreePop();
    }
}

void NearestPanel::draw_3d(Renderer& renderer, float line_width) {
    if (search) gl_geometry.draw(renderer, geometry, geometry_dirty, line_width);
}

void NearestPanel::draw_labels(const View3D& view) const {
    if (search) draw_debug_labels(geometry.labels, view);
}

}  // namespace accelviz
