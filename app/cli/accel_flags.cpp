#include "app/cli/accel_flags.h"

namespace accelviz::cli {

void add_accel_flags(CLI::App& command, AccelConfig& config) {
    command.add_option("--accel", config.type, "Acceleration structure")
        ->check(CLI::IsMember(accel_types()))
        ->capture_default_str();
}

}  // namespace accelviz::cli
