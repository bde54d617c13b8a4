#pragma once
/// A GLFW window with an OpenGL 3.3 core, forward-compatible context. Files
/// dropped on it are collected for the next frame.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "app/platform/gl_context.h"
#include "core/util/expected.h"

struct GLFWwindow;

namespace accelviz {

class GlfwWindow final : public GlContext {
public:
    /// Initialises GLFW, opens the window, makes its context current and loads
    /// `gl`. Without a display GLFW fails (error 65544, "X11: The DISPLAY
    /// environment variable is missing"): the error says so, with GLFW's words.
    static Expected<std::unique_ptr<GlfwWindow>> create(const std::string& title, int width, int height);
    ~GlfwWindow() override;  ///< closes the window and terminates GLFW
    GlfwWindow(const GlfwWindow&) = delete;
    GlfwWindow& operator=(const GlfwWindow&) = delete;

    bool make_current() override;
    int framebuffer_width() const override;
    int framebuffer_height() const override;

    bool should_close() const;
    void swap_buffers();
    /// Processes pending events; waits up to `timeout_seconds` for one first
    /// (0: do not wait).
    void process_events(double timeout_seconds);
    /// Wakes up process_events() from another thread.
    static void wake_up();
    /// Counts input and window events (mouse, keys, resize, expose), so the loop
    /// can skip drawing when nothing happened. Installed before ImGui's GLFW
    /// backend, which chains to these callbacks.
    uint64_t event_count() const { return event_count_; }
    /// Paths dropped on the window since the last call.
    std::vector<std::string> take_dropped_paths();
    /// For ImGui's GLFW backend.
    GLFWwindow* handle() const { return window_; }
    /// Full screen on the primary monitor at its current video mode, or back to the
    /// window's earlier position and size.
    void set_fullscreen(bool on);
    bool fullscreen() const { return fullscreen_; }

private:
    GlfwWindow() = default;
    static void on_drop(GLFWwindow* window, int count, const char** paths);
    static void count_event(GLFWwindow* window);
    void install_event_counters();
    GLFWwindow* window_ = nullptr;
    std::vector<std::string> dropped_;
    uint64_t event_count_ = 0;
    bool fullscreen_ = false;
    int windowed_[4] = {0, 0, 0, 0};  ///< x, y, width, height before going full screen
};

}  // namespace accelviz
