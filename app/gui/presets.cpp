#include "app/gui/presets.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>

#include "app/gui/session.h"

namespace accelviz {

namespace fs = std::filesystem;

namespace {

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

constexpr double kCaptionSeconds = 4.0;

}  // namespace

std::string find_presets_dir() {
    std::error_code ec;
    std::vector<fs::path> candidates;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        // Installed (cmake --install, the .deb): PREFIX/bin/accelviz, PREFIX/share/accelviz/presets.
        candidates.push_back(exe.parent_path().parent_path() / "share" / "accelviz" / "presets");
    }
#ifdef ACCELVIZ_SOURCE_DIR
    // A build-tree binary: the checkout it was built from.
    candidates.push_back(fs::path(ACCELVIZ_SOURCE_DIR) / "assets" / "presets");
#endif
    if (!ec) {
        const fs::path bin = exe.parent_path();
        candidates.push_back(bin / "assets" / "presets");
        candidates.push_back(bin.parent_path() / "assets" / "presets");
        candidates.push_back(bin.parent_path().parent_path() / "assets" / "presets");
    }
    for (const fs::path& dir : candidates)
        if (fs::is_directory(dir, ec)) return dir.lexically_normal().string();
    return {};
}

std::string resolve_preset(const std::string& name_or_path) {
    std::error_code ec;
    if (fs::exists(name_or_path, ec) || name_or_path.find('/') != std::string::npos) return name_or_path;
    const std::string dir = find_presets_dir();
    if (dir.empty()) return name_or_path;
    for (const std::string& file : {name_or_path, name_or_path + ".json"})
        if (fs::is_regular_file(fs::path(dir) / file, ec)) return (fs::path(dir) / file).string();
    return name_or_path;
}

std::vector<PresetInfo> list_presets(const std::string& dir) {
    std::vector<PresetInfo> out;
    std::error_code ec;
    if (dir.empty() || !fs::is_directory(dir, ec)) return out;
    for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
        if (!entry.is_regular_file(ec) || entry.path().extension() != ".json") continue;
        PresetInfo info;
        info.path = entry.path().string();
        info.name = entry.path().stem().string();
        info.title = info.name;
        std::ifstream in(entry.path());
        const nlohmann::json json = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
        if (json.is_object() && json.contains("title") && json["title"].is_string())
            info.title = json["title"].get<std::string>();
        if (json.is_object() && json.contains("caption") && json["caption"].is_string())
            info.caption = json["caption"].get<std::string>();
        out.push_back(std::move(info));
    }
    std::sort(out.begin(), out.end(), [](const PresetInfo& a, const PresetInfo& b) { return a.name < b.name; });
    return out;
}

const std::vector<PresetInfo>& PresetList::entries() {
    if (!scanned_) {
        if (!dir_set_) dir_ = find_presets_dir();
        entries_ = list_presets(dir_);
        scanned_ = true;
    }
    return entries_;
}

void PresetList::set_dir(std::string dir) {
    dir_ = std::move(dir);
    dir_set_ = true;
    scanned_ = false;
    current_ = -1;
}

void PresetList::load(int index, AppState& state, Session& session) {
    const auto& list = entries();
    if (index < 0 || size_t(index) >= list.size()) return;
    auto loaded = load_app_state_file_checked(list[size_t(index)].path);
    if (!loaded) {
        session.notify(loaded.error(), true);
        return;
    }
    // A preset is a picture: the window keeps its own UI scale and theme (set
    // for the room), and takes the rest.
    AppState next = std::move(*loaded);
    next.view.ui_scale = state.view.ui_scale;
    next.view.light_theme = state.view.light_theme;
    next.view.show_ui = state.view.show_ui;
    if (state.view.light_theme) next.view.background = state.view.background;
    session.apply_state(state, next);
    current_ = index;
    loaded_at_ = now_seconds();
    awaiting_scene_ = session.loader.busy();
}

void PresetList::opened_with(const std::string& path, const Session& session) {
    const std::vector<PresetInfo>& list = entries();
    for (size_t i = 0; i < list.size(); ++i) {
        std::error_code ec;
        if (!std::filesystem::equivalent(list[i].path, path, ec) || ec) continue;
        current_ = int(i);
        loaded_at_ = now_seconds();
        awaiting_scene_ = session.loader.busy();
        return;
    }
}

void PresetList::step(int delta, AppState& state, Session& session) {
    const int count = int(entries().size());
    if (count == 0) {
        session.notify("no presets found (looked for assets/presets in the source tree and beside the binary)", true);
        return;
    }
    int next = current_ < 0 ? (delta > 0 ? 0 : count - 1) : current_ + delta;
    next = std::clamp(next, 0, count - 1);
    if (next == current_) return;  // the first / last: stay
    load(next, state, session);
}

std::string PresetList::caption() const {
    if (current_ < 0 || size_t(current_) >= entries_.size()) return {};
    return "Preset " + std::to_string(current_ + 1) + "/" + std::to_string(entries_.size()) + ": " +
           entries_[size_t(current_)].title;
}

std::string PresetList::caption_with_text() const {
    const std::string line = caption();
    if (line.empty() || entries_[size_t(current_)].caption.empty()) return line;
    return line + "\n" + entries_[size_t(current_)].caption;
}

bool PresetList::caption_fresh() const {
    return current_ >= 0 && (awaiting_scene_ || now_seconds() - loaded_at_ < kCaptionSeconds);
}

void PresetList::scene_arrived() {
    if (!awaiting_scene_) return;
    awaiting_scene_ = false;
    loaded_at_ = now_seconds();
}

}  // namespace accelviz
