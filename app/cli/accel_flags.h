#pragma once
/// The structure flags shared by render, trace and bench.

#include <CLI/CLI.hpp>

#include "core/accel/factory.h"

namespace accelviz::cli {

/// Adds --accel and every structure's parameters to a subcommand, writing into `config`.
void add_accel_flags(CLI::App& command, AccelConfig& config);

}  // namespace accelviz::cli
