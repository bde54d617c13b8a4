#pragma once
/// Small pieces the right panels (comparison, two BVHs, construction stepper) draw
/// alike: a number formatted for a label, a worker's progress bar with its Cancel
/// button, an error line.

#include <string>

#include "core/util/work_progress.h"

namespace accelviz {

/// `value` printed with a printf `format` ("%.2f"): for labels and table cells.
std::string text_of(const char* format, double value);

/// A progress bar of `progress` (empty when null) filling `width` with a Cancel
/// button after it, which cancels `progress`.
void progress_with_cancel(WorkProgress* progress, float width);

/// "`what`: `error`" in the error colour, wrapped at the panel's edge.
void error_line(const char* what, const std::string& error);

}  // namespace accelviz
