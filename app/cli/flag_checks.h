#pragma once
/// Checks for numeric flags that say what is wrong in words a user can act on:
/// "--bins: must be a whole number from 2 to 64 (got 2.5)", where CLI11's own
/// Range said "Value 2.5 not in range 2 to 64" for a value that is no whole
/// number at all, and let NaN through its NonNegativeNumber.

#include <CLI/CLI.hpp>

namespace accelviz::cli {

/// A whole number in [lo, hi], read as CLI11 stores it (base prefixes: 0x10 is 16,
/// 010 is 8). `shown` replaces the range in --help (e.g. ">= 0").
CLI::Validator whole_number(long long lo, long long hi, const std::string& shown = "");

/// A finite number in [lo, hi] (no NaN, no infinity).
CLI::Validator number_between(double lo, double hi);

}  // namespace accelviz::cli
