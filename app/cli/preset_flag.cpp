#include "app/cli/preset_flag.h"

#include <iostream>

#include "app/gui/presets.h"

namespace accelviz::cli {

void add_preset_flag(CLI::App& command, PresetFlag& preset, AccelConfig& accel, const std::string& help,
                     const std::string& command_name) {
    command.add_option_function<std::string>(
        "--preset",
        [&preset, &accel, command_name](const std::string& name_or_path) {
            const std::string path = resolve_preset(name_or_path);
            if (!command_name.empty() && path != name_or_path)
                std::cerr << "accelviz " << command_name << ": preset " << name_or_path << ": " << path << "\n";
            preset.path = path;
            auto state = load_app_state_file(path);
            if (!state) {
                preset.error = state.error();
                return;
            }
            accel = state->accel;
            preset.state = std::move(*state);
        },
        help);
}

}  // namespace accelviz::cli
