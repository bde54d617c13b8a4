// libFuzzer target: bytes as a preset / saved window state (JSON) through
// app_state_from_json. Bad JSON or a bad value must come back as an error, never
// as a crash or an escaped exception; a state that is read must survive a round
// trip through to_json unchanged.
#include <cstdint>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "app/gui/app_state.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace accelviz;
    const nlohmann::json json = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
    if (json.is_discarded()) return 0;
    auto state = app_state_from_json(json);
    if (!state) return 0;
    const nlohmann::json written = to_json(*state);
    auto again = app_state_from_json(written);
    if (!again || to_json(*again) != written) std::abort();
    return 0;
}
