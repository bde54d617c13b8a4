#pragma once
/// The interactive window: `accelviz [SCENE] [flags]` with no subcommand.

#include <string>

#include "app/gui/app_state.h"

namespace accelviz {

/// Opens the window on `state` (its scene loads on a worker thread while the
/// window is already up) and runs until it is closed. Returns the process exit
/// code; without a display it prints why, suggests `accelviz render`, returns 1.
/// `preset_path`: the preset file `state` came from, if any (one of the shipped
/// presets becomes the current one: its caption shows, PageDown goes on from it).
/// `lecture`: start in lecture mode (full screen, no panels, the caption bar);
/// `first_preset`: open the first shipped preset instead of `state`'s scene.
int run_window(AppState state, const std::string& preset_path = "", bool lecture = false, bool first_preset = false);

}  // namespace accelviz
