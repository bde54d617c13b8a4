#pragma once
/// The interactive window: `accelviz [SCENE]` with no subcommand.

#include "app/gui/app_state.h"

namespace accelviz {

/// Opens the window on `state` (its scene loads on a worker thread while the
/// window is already up) and runs until it is closed. Returns the process exit
/// code; without a display it prints why, suggests `accelviz render`, returns 1.
int run_window(AppState state);

}  // namespace accelviz
