#include "app/cli/commands.h"

namespace accelviz::cli {

// Placeholder: `trace` arrives with the BVH work.
Command register_trace(CLI::App&) { return {}; }

}  // namespace accelviz::cli
