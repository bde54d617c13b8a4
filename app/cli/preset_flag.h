#pragma once
/// --preset, as `render` and the window take it: a saved window state (a JSON file,
/// or a shipped preset's name), read while the command line is parsed.

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "app/gui/app_state.h"

namespace accelviz::cli {

struct PresetFlag {
    std::optional<AppState> state;  ///< the preset read (none: not given, or unreadable)
    std::string error;              ///< why it could not be read
    std::string path;               ///< its file, for messages
};

/// Adds --preset to `command`, before the structure flags: CLI11 applies options in
/// the order they were added, so the structure flags given then land on the preset's
/// structure, which this writes into `accel`. `command_name` (e.g. "render"): say on
/// stderr which file a preset's name resolved to; empty: say nothing.
void add_preset_flag(CLI::App& command, PresetFlag& preset, AccelConfig& accel, const std::string& help,
                     const std::string& command_name = "");

}  // namespace accelviz::cli
