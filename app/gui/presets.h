#pragma once
/// Presets: saved AppStates (JSON) in assets/presets/, named so that they sort
/// in lecture order ("01-naive-cost.json", ...). PageDown / PageUp step through
/// them (a presentation clicker sends those keys); the Scene panel lists them.
/// A preset may carry a "title" and a "caption" (one or two sentences: what the
/// picture proves), shown when it loads and in lecture mode's caption bar;
/// AppState ignores both.

#include <string>
#include <vector>

#include "app/gui/app_state.h"

namespace accelviz {

struct Session;

struct PresetInfo {
    std::string path;   ///< the JSON file
    std::string name;   ///< file name without ".json" ("01-naive-cost")
    std::string title;  ///< its "title", or the name
    std::string caption;  ///< its "caption" (may be empty)
};

/// Where the shipped presets are: PREFIX/share/accelviz/presets for a binary in
/// PREFIX/bin (installed), else <source dir>/assets/presets (ACCELVIZ_SOURCE_DIR, the
/// checkout a build-tree binary was built from), else assets/presets next to the
/// binary or one or two directories up. Empty if none exists.
std::string find_presets_dir();

/// A preset given by name ("30-grid-stadium", with or without ".json") as its file
/// in find_presets_dir(); anything that is a file, or has a '/', is returned as it is.
std::string resolve_preset(const std::string& name_or_path);

/// The *.json files of `dir`, sorted by file name.
std::vector<PresetInfo> list_presets(const std::string& dir);

/// The window's presets: the list (read once) and which one is on.
class PresetList {
public:
    /// Reads the directory the first time (find_presets_dir() unless set_dir was called).
    const std::vector<PresetInfo>& entries();
    /// Lists `dir` instead (empty: no presets; headless frames use that, so that
    /// golden images do not change when a preset is added).
    void set_dir(std::string dir);
    const std::string& dir() const { return dir_; }
    /// Loads entry `index` (through Session::apply_state: the scene loads and the
    /// structure builds on the worker). A bad file: a message, nothing changes.
    void load(int index, AppState& state, Session& session);
    /// The next (+1, PageDown) or previous (-1, PageUp) preset; from none, the first / last.
    void step(int delta, AppState& state, Session& session);
    /// The window was opened on the preset in file `path` (`accelviz --preset`): if it is
    /// one of the list, it becomes the current one (its caption shows, PageDown goes
    /// on from it). `session` tells whether its scene is still coming.
    void opened_with(const std::string& path, const Session& session);
    /// The preset last loaded (-1: none).
    int current() const { return current_; }
    /// "Preset 3/11: title" (empty when none is loaded): one line, for the status bar.
    std::string caption() const;
    /// The same with the preset's caption on the next line: over the view when it loads.
    std::string caption_with_text() const;
    /// True while a preset's scene or structure is still coming and for a few seconds
    /// after it is on screen: its caption is shown over the view. (Counting from the
    /// key press instead, a big scene's caption was gone before the scene appeared.)
    bool caption_fresh() const;
    /// The window has taken the worker's result (a scene, a structure or an error):
    /// the caption's few seconds start now.
    void scene_arrived();

private:
    bool scanned_ = false;
    bool dir_set_ = false;
    std::string dir_;
    std::vector<PresetInfo> entries_;
    int current_ = -1;
    double loaded_at_ = -1e9;  ///< steady clock, seconds: when the preset's scene arrived
    bool awaiting_scene_ = false;  ///< the preset's load or build is still on the worker
};

}  // namespace accelviz
