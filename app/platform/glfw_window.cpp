#include "app/platform/glfw_window.h"

#define GLFW_INCLUDE_NONE  // GL comes from our loader, never from <GL/gl.h>
#include <GLFW/glfw3.h>

#include <string>
#include <utility>

#include "app/platform/gl_lookup.h"

namespace accelviz {

namespace {

/// GLFW reports errors through a callback; keep the last one for our message.
std::string g_last_glfw_error;

void remember_glfw_error(int code, const char* description) {
    g_last_glfw_error = std::string(description ? description : "unknown error") + " (GLFW error " +
                        std::to_string(code) + ")";
}

void* glfw_lookup(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

}  // namespace

Expected<std::unique_ptr<GlfwWindow>> GlfwWindow::create(const std::string& title, int width, int height) {
    glfwSetErrorCallback(remember_glfw_error);
    g_last_glfw_error.clear();
    if (!glfwInit()) return Error{"cannot open a window: " + g_last_glfw_error};

    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_DEPTH_BITS, 24);
    glfwWindowHint(GLFW_STENCIL_BITS, 8);
    std::unique_ptr<GlfwWindow> window(new GlfwWindow());
    window->window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window->window_) {
        glfwTerminate();
        return Error{"cannot open an OpenGL 3.3 core window: " + g_last_glfw_error};
    }
    glfwSetWindowUserPointer(window->window_, window.get());
    window->install_event_counters();
    glfwSetDropCallback(window->window_, &GlfwWindow::on_drop);
    std::string missing;
    glfwMakeContextCurrent(window->window_);
    if (!load_gl(&glfw_lookup, &missing)) return Error{"the OpenGL driver lacks " + missing};
    glfwSwapInterval(1);
    return window;
}

GlfwWindow::~GlfwWindow() {
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

bool GlfwWindow::make_current() {
    glfwMakeContextCurrent(window_);
    return load_gl(&glfw_lookup, nullptr);
}

int GlfwWindow::framebuffer_width() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    return w;
}

int GlfwWindow::framebuffer_height() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    return h;
}

bool GlfwWindow::should_close() const { return glfwWindowShouldClose(window_); }

void GlfwWindow::swap_buffers() { glfwSwapBuffers(window_); }

void GlfwWindow::set_fullscreen(bool on) {
    if (on == fullscreen_) return;
    if (on) {
        GLFWmonitor* monitor = glfwGetPrimaryMonitor();
        const GLFWvidmode* mode = monitor ? glfwGetVideoMode(monitor) : nullptr;
        if (!mode) return;  // no monitor to fill: stay a window
        glfwGetWindowPos(window_, &windowed_[0], &windowed_[1]);
        glfwGetWindowSize(window_, &windowed_[2], &windowed_[3]);
        glfwSetWindowMonitor(window_, monitor, 0, 0, mode->width, mode->height, mode->refreshRate);
    } else {
        glfwSetWindowMonitor(window_, nullptr, windowed_[0], windowed_[1], windowed_[2], windowed_[3], GLFW_DONT_CARE);
    }
    fullscreen_ = on;
}

void GlfwWindow::process_events(double timeout_seconds) {
    if (timeout_seconds > 0)
        glfwWaitEventsTimeout(timeout_seconds);
    else
        glfwPollEvents();
}

void GlfwWindow::wake_up() { glfwPostEmptyEvent(); }

std::vector<std::string> GlfwWindow::take_dropped_paths() { return std::exchange(dropped_, {}); }

void GlfwWindow::on_drop(GLFWwindow* handle, int count, const char** paths) {
    auto* window = static_cast<GlfwWindow*>(glfwGetWindowUserPointer(handle));
    for (int i = 0; i < count; ++i) window->dropped_.emplace_back(paths[i]);
    ++window->event_count_;
}

void GlfwWindow::count_event(GLFWwindow* handle) {
    ++static_cast<GlfwWindow*>(glfwGetWindowUserPointer(handle))->event_count_;
}

void GlfwWindow::install_event_counters() {
    GLFWwindow* w = window_;
    glfwSetCursorPosCallback(w, [](GLFWwindow* h, double, double) { count_event(h); });
    glfwSetMouseButtonCallback(w, [](GLFWwindow* h, int, int, int) { count_event(h); });
    glfwSetScrollCallback(w, [](GLFWwindow* h, double, double) { count_event(h); });
    glfwSetKeyCallback(w, [](GLFWwindow* h, int, int, int, int) { count_event(h); });
    glfwSetCharCallback(w, [](GLFWwindow* h, unsigned int) { count_event(h); });
    glfwSetCursorEnterCallback(w, [](GLFWwindow* h, int) { count_event(h); });
    glfwSetWindowFocusCallback(w, [](GLFWwindow* h, int) { count_event(h); });
    glfwSetFramebufferSizeCallback(w, [](GLFWwindow* h, int, int) { count_event(h); });
    glfwSetWindowRefreshCallback(w, [](GLFWwindow* h) { count_event(h); });
}

}  // namespace accelviz
