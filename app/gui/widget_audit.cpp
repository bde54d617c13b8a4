#include "app/gui/widget_audit.h"

#include <cstring>
#include <unordered_map>
#include <unordered_set>

#include <imgui.h>
#include <imgui_internal.h>

namespace accelviz::widget_audit {

namespace {

struct Recorder {
    bool on = false;
    std::vector<Widget> widgets;
    std::vector<Duplicate> duplicates;
    std::unordered_set<uint32_t> seen;
    std::unordered_map<uint32_t, std::string> labels;  ///< ID -> the label it was hashed from, this frame

    void clear() {
        widgets.clear();
        duplicates.clear();
        seen.clear();
        labels.clear();
    }
};

Recorder& recorder() {
    static Recorder r;
    return r;
}

}  // namespace

void set_enabled(bool on) {
    recorder().on = on;
    recorder().clear();
}

bool enabled() { return recorder().on; }

void begin_frame() {
    if (recorder().on) recorder().clear();
}

const std::vector<Widget>& widgets() { return recorder().widgets; }
const std::vector<Duplicate>& duplicates() { return recorder().duplicates; }

std::string active_text_field() {
    const ImGuiContext& g = *ImGui::GetCurrentContext();
    if (!ImGui::GetIO().WantTextInput || g.ActiveId == 0) return "";
    for (const Widget& w : recorder().widgets)
        if (w.id == g.ActiveId) return w.label;
    return "";
}

std::string visible_text(const std::string& label) {
    const size_t hashes = label.find("##");
    return hashes == std::string::npos ? label : label.substr(0, hashes);
}

}  // namespace accelviz::widget_audit

// The two ImGui functions routed through here by `-Wl,--wrap=SYMBOL` (their
// mangled names): calls from imgui_widgets.o and imgui_tables.o reach
// __wrap_SYMBOL, and __real_SYMBOL is ImGui's own function.
extern "C" {
ImGuiID __real__ZN11ImGuiWindow5GetIDEPKcS1_(ImGuiWindow* window, const char* str, const char* str_end);
bool __real__ZN5ImGui7ItemAddERK6ImRectjPS1_i(const ImRect& bb, ImGuiID id, const ImRect* nav_bb, ImGuiItemFlags flags);

/// ImGuiWindow::GetID(const char* label, const char* label_end).
ImGuiID __wrap__ZN11ImGuiWindow5GetIDEPKcS1_(ImGuiWindow* window, const char* str, const char* str_end) {
    const ImGuiID id = __real__ZN11ImGuiWindow5GetIDEPKcS1_(window, str, str_end);
    auto& r = accelviz::widget_audit::recorder();
    if (r.on && str) r.labels[id] = str_end ? std::string(str, str_end) : std::string(str);
    return id;
}

/// ImGui::ItemAdd(const ImRect& bb, ImGuiID id, const ImRect* nav_bb, ImGuiItemFlags flags).
bool __wrap__ZN5ImGui7ItemAddERK6ImRectjPS1_i(const ImRect& bb, ImGuiID id, const ImRect* nav_bb, ImGuiItemFlags flags) {
    auto& r = accelviz::widget_audit::recorder();
    if (r.on && id != 0) {
        accelviz::widget_audit::Widget w;
        w.id = id;
        if (auto it = r.labels.find(id); it != r.labels.end()) w.label = it->second;
        const ImGuiWindow* window = ImGui::GetCurrentWindowRead();
        if (window && window->Name) w.window = window->Name;
        w.hidden = window && window->Hidden;
        const ImRect& hit = nav_bb ? *nav_bb : bb;  // a combo or slider takes clicks on its frame, not its label
        w.x0 = hit.Min.x;
        w.y0 = hit.Min.y;
        w.x1 = hit.Max.x;
        w.y1 = hit.Max.y;
        if (!r.seen.insert(id).second) r.duplicates.push_back({id, w.label, w.window});
        r.widgets.push_back(std::move(w));
    }
    return __real__ZN5ImGui7ItemAddERK6ImRectjPS1_i(bb, id, nav_bb, flags);
}
}
