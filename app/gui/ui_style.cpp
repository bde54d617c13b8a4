#include "app/gui/ui_style.h"

#include <filesystem>

#include <imgui.h>

#include "app/gl/imgui_renderer.h"
#include "app/gl/renderer.h"

namespace accelviz {

namespace {

/// Our tweaks on top of ImGui's dark or light colours, at scale 1.
ImGuiStyle base_style(bool light) {
    ImGuiStyle style;
    if (light) {
        ImGui::StyleColorsLight(&style);
        style.Colors[ImGuiCol_WindowBg] = ImVec4(0.96f, 0.96f, 0.95f, 1.0f);
        style.Colors[ImGuiCol_Text] = ImVec4(0.05f, 0.05f, 0.05f, 1.0f);  // strong contrast for projectors
    } else {
        ImGui::StyleColorsDark(&style);
        style.Colors[ImGuiCol_WindowBg] = ImVec4(0.09f, 0.10f, 0.12f, 1.0f);
    }
    style.WindowRounding = 0.0f;  // fixed panels, not floating windows
    style.WindowBorderSize = 0.0f;
    style.FrameRounding = 3.0f;
    style.GrabRounding = 3.0f;
    style.FramePadding = ImVec2(6.0f, 4.0f);
    style.ItemSpacing = ImVec2(8.0f, 6.0f);
    style.WindowPadding = ImVec2(10.0f, 10.0f);
    return style;
}

}  // namespace

void UiStyle::apply(const ViewSettings& view, Renderer& renderer) {
    if (view.ui_scale == ui_scale && view.light_theme == light_theme) return;
    ImGuiIO& io = ImGui::GetIO();

    if (view.ui_scale != ui_scale) {
        const float pixels = float(font_pixels(view.ui_scale));
        io.Fonts->Clear();
        std::error_code error;
        using_fallback_font = !std::filesystem::is_regular_file(kUiFontPath, error);
        ImFont* font = nullptr;
        if (!using_fallback_font) font = io.Fonts->AddFontFromFileTTF(kUiFontPath, pixels);
        if (!font) {  // ImGui's built-in ProggyClean: always there, blurry when scaled
            using_fallback_font = true;
            ImFontConfig config;
            config.SizePixels = pixels;
            io.Fonts->AddFontDefault(&config);
        }
        renderer.imgui().upload_fonts();
    }

    ImGui::GetStyle() = base_style(view.light_theme);
    ImGui::GetStyle().ScaleAllSizes(view.ui_scale);
    ui_scale = view.ui_scale;
    light_theme = view.light_theme;
}

}  // namespace accelviz
