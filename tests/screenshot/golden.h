#pragma once
/// Golden-image comparison for the screenshot tests.
///
/// Tolerance (stated once, used by every golden test): a pixel matches when each
/// of its R, G, B channels is within kChannelTolerance of the golden image; an
/// image matches when at most kMaxMismatchFraction of its pixels do not (room for
/// a different Mesa/LLVM rounding an edge or a glyph differently; llvmpipe itself
/// is deterministic, so on one machine the difference is 0).
///
/// On a mismatch the test writes, under the build's screenshot-out/ directory,
/// NAME.png (what was rendered) and NAME.diff.png (the golden dimmed to grey with
/// mismatching pixels in red), and says where they are.
///
/// To regenerate the goldens after an intended change: run the tests with the
/// environment variable ACCELVIZ_UPDATE_GOLDEN=1 (or pass --update-golden to
/// screenshot_tests); they then write golden/NAME.png and pass. Look at the new
/// images before committing them.

#include <string>

#include <gtest/gtest.h>

#include "app/gui/app_state.h"
#include "app/gui/headless.h"
#include "app/gui/session.h"
#include "core/render/image.h"

namespace accelviz::testing {

inline constexpr int kChannelTolerance = 3;
inline constexpr double kMaxMismatchFraction = 0.001;

/// True when goldens are to be rewritten (ACCELVIZ_UPDATE_GOLDEN=1 or --update-golden).
bool update_golden_mode();
void set_update_golden_mode(bool on);

/// Compares `actual` with golden/NAME.png (see the tolerance above).
::testing::AssertionResult matches_golden(const Image& actual, const std::string& name);

/// Renders `view` of `state` headless (render_gui_view_headless) at width x height
/// and compares it with golden/NAME.png; a failed render fails with its message.
::testing::AssertionResult view_matches_golden(const AppState& state, WindowView view, int width, int height,
                                               const std::string& name);

/// Makes the comparison panel's figures the same every run: its clock moves 1 ms each
/// time it is read (every build takes 1 ms, every pass of the rays 1 ms), and naive
/// traces 16 rays, so it is the slowest per ray and the chart has its break-even
/// points. (core's tests check the measuring itself.)
void use_ticking_clock(Session& session);
/// The clock use_ticking_clock gives the panel: 1 ms more each time it is read.
MeasureClock ticking_clock();

/// Where the tests write what they rendered (created on demand).
std::string screenshot_out_dir();

/// Draws frames until the session's loader has nothing left to hand over (at most
/// `seconds`), then one more: a window session after a load, a rebuild or a drop.
void draw_until_loaded(HeadlessApp& app, AppState& state, int seconds = 20);

}  // namespace accelviz::testing
