#include "app/gui/panel_widgets.h"

#include <algorithm>
#include <cstdio>

#include <imgui.h>

namespace accelviz {

std::string text_of(const char* format, double value) {
    char text[64];
    std::snprintf(text, sizeof text, format, value);
    return text;
}

void progress_with_cancel(WorkProgress* progress, float width) {
    const float button = ImGui::CalcTextSize("Cancel").x + 2.0f * ImGui::GetStyle().FramePadding.x;
    ImGui::ProgressBar(progress ? float(progress->fraction()) : 0.0f,
                       ImVec2(std::max(1.0f, width - button - ImGui::GetStyle().ItemSpacing.x), 0.0f));
    ImGui::SameLine();
    if (ImGui::Button("Cancel") && progress) progress->cancel();
}

void error_line(const char* what, const std::string& error) {
    ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(255, 120, 100, 255));
    ImGui::TextWrapped("%s: %s", what, error.c_str());
    ImGui::PopStyleColor();
}

}  // namespace accelviz
