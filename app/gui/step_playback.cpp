#include "app/gui/step_playback.h"

#include <algorithm>
#include <cfloat>
#include <cstdio>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key codes only (ImGui 1.86 indexes io.KeysDown by the GLFW backend's codes)
#include <imgui.h>

namespace accelviz {

void StepPlayback::advance(size_t& step, size_t end, double seconds) {
    if (!playing) return;
    play_clock += seconds * speed;
    while (play_clock >= 1.0 && step < end) {
        ++step;
        play_clock -= 1.0;
        scroll_to_current = true;
    }
    if (step >= end) playing = false;
}

void StepPlayback::draw_buttons(size_t& step, size_t end) {
    step = std::min(step, end);
    const size_t before = step;
    if (ImGui::Button("|<")) step = 0;
    ImGui::SameLine();
    if (ImGui::Button("<") && step > 0) --step;
    ImGui::SameLine();
    if (ImGui::Button(playing ? "Pause###play" : "Play###play")) {  // one ID whichever it reads
        playing = !playing;
        if (playing && step >= end) step = 0;
        play_clock = 0;
    }
    ImGui::SameLine();
    if (ImGui::Button(">") && step < end) ++step;
    ImGui::SameLine();
    if (ImGui::Button(">|")) step = end;
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-FLT_MIN);
    ImGui::SliderFloat("##speed", &speed, 0.5f, 200.0f, "%.1f events/s", ImGuiSliderFlags_Logarithmic);
    int k = int(step);
    ImGui::SetNextItemWidth(-FLT_MIN);
    if (ImGui::SliderInt("##scrubber", &k, 0, int(end), "step %d", ImGuiSliderFlags_AlwaysClamp)) step = size_t(k);
    if (step != before) scroll_to_current = true;
}

void StepPlayback::handle_keys(size_t& step, size_t end) {
    step = std::min(step, end);
    const size_t before = step;
    if (!ImGui::GetIO().KeyShift) {
        if (ImGui::IsKeyPressed(GLFW_KEY_RIGHT, true) && step < end) ++step;
        if (ImGui::IsKeyPressed(GLFW_KEY_LEFT, true) && step > 0) --step;
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_HOME, false)) step = 0;
    if (ImGui::IsKeyPressed(GLFW_KEY_END, false)) step = end;
    if (ImGui::IsKeyPressed(GLFW_KEY_SPACE, false)) {
        playing = !playing;
        if (playing && step >= end) step = 0;
        play_clock = 0;
    }
    if (step != before) scroll_to_current = true;
}

void StepPlayback::draw_event_list(const std::vector<TraversalEvent>& events, size_t& step, int rows,
                                   const std::function<std::string(const TraversalEvent&)>& describe) {
    const float height = float(rows) * ImGui::GetTextLineHeightWithSpacing();
    if (!ImGui::BeginChild("##events", ImVec2(0, height), true)) {
        ImGui::EndChild();
        return;
    }
    const size_t current = step;  // row i is event i; the current one is events[step - 1]
    ImGuiListClipper clipper;
    clipper.Begin(int(events.size()));
    if (scroll_to_current && current > 0) clipper.ForceDisplayRangeByIndices(int(current) - 1, int(current));
    while (clipper.Step()) {
        for (int i = clipper.DisplayStart; i < clipper.DisplayEnd; ++i) {
            const bool is_current = size_t(i) + 1 == current;
            char label[320];
            std::snprintf(label, sizeof label, "%5d  %s", i + 1, describe(events[size_t(i)]).c_str());
            if (size_t(i) >= current) ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
            if (ImGui::Selectable(label, is_current)) step = size_t(i) + 1;
            if (size_t(i) >= current) ImGui::PopStyleColor();
            if (is_current && scroll_to_current) ImGui::SetScrollHereY(0.5f);
        }
    }
    if (scroll_to_current && current == 0) ImGui::SetScrollY(0);
    scroll_to_current = false;
    ImGui::EndChild();
}

}  // namespace accelviz
