#pragma once
/// Fonts and colours of the panels, rebuilt when the View settings change: the
/// font is re-rasterised at the new pixel size (sharp text on a projector,
/// not a scaled-up bitmap), and every ImGui size is scaled with it.

#include "app/gui/app_state.h"
#include "core/render/image.h"

namespace accelviz {

class Renderer;

/// The style last applied, so it is rebuilt only on a change.
struct UiStyle {
    float ui_scale = 0;  ///< 0: nothing applied yet
    bool light_theme = false;
    bool using_fallback_font = false;  ///< the TrueType font was not found: ImGui's built-in bitmap font

    /// Applies `view` if it differs from what was applied. Call between frames
    /// (before ImGui::NewFrame), with the renderer's context current.
    void apply(const ViewSettings& view, Renderer& renderer);
};

/// The TrueType font of the panels: the one the CPU images' labels use too.
inline constexpr const char* kUiFontPath = kDejaVuSansPath;

}  // namespace accelviz
