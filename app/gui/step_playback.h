#pragma once
/// Stepping through a recorded list of events in a panel: the buttons, the scrubber,
/// playback at a speed, the keys and the event list. The ray stepper and the
/// nearest-point stepper share it; the step itself lives in AppState (a preset or a
/// saved state reproduces it), playback does not (no animation in a saved frame).

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "core/traversal/events.h"

namespace accelviz {

struct StepPlayback {
    bool playing = false;
    float speed = 4.0f;       ///< events per second
    double play_clock = 0;    ///< seconds accumulated towards the next step
    bool scroll_to_current = true;

    /// A new recording: stop, and show its current event.
    void restart() {
        playing = false;
        scroll_to_current = true;
    }
    /// While playing, `speed` events a second (`seconds` since the last frame).
    void advance(size_t& step, size_t end, double seconds);
    /// |< < Play > >|, the speed and the scrubber.
    void draw_buttons(size_t& step, size_t end);
    /// Right / Left step, Home / End, Space plays (call when ImGui does not want the keyboard).
    void handle_keys(size_t& step, size_t end);
    /// `rows` rows of the event list, events[i] as row i + 1 (`describe`); the current
    /// event, events[step - 1], highlighted and scrolled to; a click steps to a row.
    void draw_event_list(const std::vector<TraversalEvent>& events, size_t& step, int rows,
                         const std::function<std::string(const TraversalEvent&)>& describe);
};

}  // namespace accelviz
