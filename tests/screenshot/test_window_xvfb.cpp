// A real GLFW window (run under Xvfb by CTest: xvfb-run -a -s '-screen 0
// 1280x800x24') draws frames with draw_frame(); its pixels, read back with
// glReadPixels, must equal the OSMesa render of the same state and view (the
// golden tests' path). Same code, two contexts, same picture.
#include <cstdlib>

#include <gtest/gtest.h>
#include <imgui.h>

#include "app/gl/renderer.h"
#include "app/gui/draw_frame.h"
#include "app/gui/headless.h"
#include "app/gui/session.h"
#include "app/platform/glfw_window.h"
#include "golden.h"

namespace accelviz {
namespace {

struct WindowFrame {
    Image colour;
    int frames = 0;
};

/// Opens a window, draws `frames` frames of `state` like the window loop does
/// (but with ImGui's input left empty: no pointer, no keys), reads back the last.
Expected<WindowFrame> render_in_window(const AppState& initial, bool draw_ui, int width, int height, int frames) {
    auto window = GlfwWindow::create("accelviz window test", width, height);
    if (!window) return Error{window.error()};
    if ((*window)->framebuffer_width() != width || (*window)->framebuffer_height() != height)
        return Error{"the window's framebuffer is not the size asked for"};
    ImGuiContext* imgui = ImGui::CreateContext();
    ImGui::SetCurrentContext(imgui);
    ImGui::GetIO().IniFilename = nullptr;
    WindowFrame out;
    {
        auto renderer = Renderer::create();
        if (!renderer) return Error{renderer.error()};
        AppState state = initial;
        auto loaded = load_and_build(state.scene, state.accel);
        if (!loaded) return Error{loaded.error()};
        Session session;
        session.presets.set_dir("");  // as headless frames: no preset list in the sidebar
        session.set_scene(state, std::move(*loaded), state.camera.has_value());
        FrameInput input;
        input.width = width;
        input.height = height;
        input.draw_ui = draw_ui;
        input.deterministic = true;
        for (int i = 0; i < frames; ++i) {
            (*window)->process_events(0.0);
            ImGui::GetIO().DisplaySize = ImVec2(float(width), float(height));
            ImGui::GetIO().DeltaTime = 1.0f / 60.0f;
            draw_frame(state, **renderer, session, input);
            if (i + 1 == frames) out.colour = (*renderer)->read_colour({0, 0, width, height});  // the back buffer
            (*window)->swap_buffers();
            ++out.frames;
        }
    }
    ImGui::DestroyContext(imgui);
    return out;
}

/// Pixels whose channels differ by more than the golden tolerance.
size_t differing_pixels(const Image& a, const Image& b) {
    size_t n = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        const Rgb p = a.pixels[i], q = b.pixels[i];
        if (std::abs(p.r - q.r) > testing::kChannelTolerance || std::abs(p.g - q.g) > testing::kChannelTolerance ||
            std::abs(p.b - q.b) > testing::kChannelTolerance)
            ++n;
    }
    return n;
}

void expect_window_equals_osmesa(const AppState& state, WindowView view, const std::string& name) {
    constexpr int kWidth = 640, kHeight = 400;
    auto window = render_in_window(state, view == WindowView::Gui, kWidth, kHeight, 3);
    ASSERT_TRUE(window) << window.error();
    auto headless = render_gui_view_headless(state, view, kWidth, kHeight);
    ASSERT_TRUE(headless) << headless.error();
    const std::string out = testing::screenshot_out_dir();
    (void)write_png(window->colour, out + "/" + name + "_window.png");
    (void)write_png(*headless, out + "/" + name + "_osmesa.png");
    ASSERT_EQ(window->colour.width, headless->width);
    ASSERT_EQ(window->colour.height, headless->height);
    const size_t differing = differing_pixels(window->colour, *headless);
    EXPECT_LE(double(differing) / double(kWidth * kHeight), testing::kMaxMismatchFraction)
        << differing << " pixels differ; see " << out << "/" << name << "_window.png and _osmesa.png";
}

TEST(XvfbWindow, GuiFrameInWindowEqualsOsMesaRender) {
    AppState state;
    state.scene = "builtin:cube";
    expect_window_equals_osmesa(state, WindowView::Gui, "xvfb_cube_gui");
}

TEST(XvfbWindow, StructureViewInWindowEqualsOsMesaRender) {
    AppState state;
    state.scene = "builtin:teapot?n=4";
    state.accel.type = AccelType::Bvh;
    state.view.line_width = 2.5f;  // the geometry-shader path too
    expect_window_equals_osmesa(state, WindowView::Structure, "xvfb_teapot_bvh");
}

TEST(XvfbWindow, WithoutDisplayTheWindowFailsWithGlfwsReason) {
    const char* display = std::getenv("DISPLAY");
    const std::string saved = display ? display : "";
    unsetenv("DISPLAY");
    auto window = GlfwWindow::create("no display", 64, 64);
    if (!saved.empty()) setenv("DISPLAY", saved.c_str(), 1);
    ASSERT_FALSE(window);
    EXPECT_NE(window.error().find("DISPLAY"), std::string::npos) << window.error();
}

}  // namespace
}  // namespace accelviz
