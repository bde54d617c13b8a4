#include "app/cli/flag_checks.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace accelviz::cli {

namespace {

/// A bound as a person writes it: 64, 0.999, 1e-06, 1000000, 1e+09.
std::string shown(double value) {
    char text[32];
    const bool whole = value == std::floor(value) && std::fabs(value) < 1e7;
    std::snprintf(text, sizeof text, whole ? "%.0f" : "%g", value);
    return text;
}

}  // namespace

CLI::Validator whole_number(long long lo, long long hi, const std::string& help) {
    const std::string range = std::to_string(lo) + " to " + std::to_string(hi);
    return CLI::Validator(
        [lo, hi, range](std::string& value) -> std::string {
            const char* begin = value.c_str();
            char* end = nullptr;
            errno = 0;
            const long long n = std::strtoll(begin, &end, 0);  // base as CLI11's own conversion
            const bool whole = end != begin && *end == '\0' && errno == 0;
            if (whole && n >= lo && n <= hi) return {};
            return "must be a whole number from " + range + " (got " + value + ")";
        },
        help.empty() ? range : help);
}

CLI::Validator number_between(double lo, double hi) {
    const std::string range = shown(lo) + " to " + shown(hi);
    return CLI::Validator(
        [lo, hi, range](std::string& value) -> std::string {
            const char* begin = value.c_str();
            char* end = nullptr;
            const double x = std::strtod(begin, &end);
            const bool number = end != begin && *end == '\0' && std::isfinite(x);
            if (number && x >= lo && x <= hi) return {};
            return "must be a number from " + range + " (got " + value + ")";
        },
        range);
}

}  // namespace accelviz::cli
