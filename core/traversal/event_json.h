#pragma once
/// Events, counters and hits as JSON: what `accelviz trace --json` prints and what
/// the GUI can save or load. One object per event with "kind" (events.cpp names,
/// e.g. "box_test") and only the fields that kind uses (see events.h).
///
/// Numbers: floats are written with enough digits to read back the same float.
/// JSON has no infinity or NaN, so those are written as the strings "inf",
/// "-inf" and "nan" (e.g. t of a miss, or t_enter of a box the ray never enters).
/// A missing triangle id (Hit::kNoHit) is written as null.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/traversal/observers.h"

namespace accelviz {

/// A float as JSON: a number if finite, else "inf", "-inf" or "nan".
nlohmann::json float_to_json(float value);

nlohmann::json to_json(const TraversalEvent& event);
nlohmann::json to_json(const std::vector<TraversalEvent>& events);
nlohmann::json to_json(const Counters& counters);
/// One event as one line of text: its kind, then its JSON fields as key=value
/// (what `trace` prints and the stepper's event list shows).
std::string describe(const TraversalEvent& event);

/// {"hit": false} for a miss, else {"hit": true, "tri", "t", "u", "v"}.
nlohmann::json to_json(const Hit& hit);

}  // namespace accelviz
