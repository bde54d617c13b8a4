#include "app/cli/commands.h"

namespace accelviz::cli {

Command register_render(CLI::App&) { return {}; }

}  // namespace accelviz::cli
