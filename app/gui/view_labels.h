#pragma once
/// The text written over the 3D view: messages (loading, errors), the preset's
/// caption, the structure overlay's legend and, in the split view, what each half
/// shows with the work its renderer did and its picture's colour scale.
///
/// One owner lays them out: each half of the view stacks its labels down from its
/// top edge and up from its bottom edge, each at most as wide as the half, so no
/// label covers another at any window size; where the room runs out, a label's
/// detail is cut to the lines that fit (ending in "..."). The CPU pictures in the
/// split view carry no text of their own: their titles and legends are drawn here,
/// in the window's font at the UI scale.

#include "app/gl/view3d.h"
#include "app/gui/app_state.h"
#include "app/gui/session.h"

namespace accelviz {

/// The rectangles of the 3D view (see compute_layout in draw_frame.cpp).
struct ViewAreas {
    ViewRect view;      ///< the whole view
    ViewRect gl_view;   ///< OpenGL's picture: the view, or its left half when split
    ViewRect ray_view;  ///< split: the ray caster's half
    bool split = false;
};

/// The point light's marker: its radius in pixels (a drag that starts within it
/// moves the light; draw_frame.cpp).
inline double light_marker_radius(float ui_scale) { return 12.0 * ui_scale; }

/// Draws all of it (ImGui windows; call between NewFrame and Render).
/// `structure_legend`: the overlay's legend belongs in the OpenGL half this frame.
void draw_view_labels(const AppState& state, Session& session, const ViewAreas& areas, bool structure_legend,
                      bool deterministic);

}  // namespace accelviz
