#include "app/cli/commands.h"

namespace accelviz::cli {

// Placeholder: `bench` arrives with the BVH work.
Command register_bench(CLI::App&) { return {}; }

}  // namespace accelviz::cli
