#pragma once
/// Every widget ImGui laid out in a frame: its ID, label, window and rectangle.
///
/// Two uses:
///  - a check that no two widgets drawn in one frame share an ID. ImGui 1.86 does
///    not warn; the second widget then loses its clicks to the first (a combo
///    labelled like the section header above it could not be opened);
///  - scripted tests of the real window, which find a widget by its label and
///    click the middle of its rectangle (see ACCELVIZ_UI_SNAPSHOT in window.cpp).
///
/// How it sees them: the link step routes ImGui's own calls to
/// ImGuiWindow::GetID(label) and ImGui::ItemAdd(rect, id), made inside Debian's
/// prebuilt libimgui.a, through widget_audit.cpp (GNU ld --wrap, set on the
/// accelviz_gui target), which records and forwards them. Recording is off until
/// set_enabled(true); off, each call costs one branch.

#include <cstdint>
#include <string>
#include <vector>

namespace accelviz::widget_audit {

/// One widget of a frame, as ImGui placed it (pixels, origin top left).
struct Widget {
    uint32_t id = 0;
    std::string label;   ///< the label it was made with, "##" suffix included ("" if unknown)
    std::string window;  ///< the ImGui window it is in ("##sidebar", "##Combo_00", ...)
    float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< where a click reaches it
    bool hidden = false;  ///< its window is laid out but not shown (a popup's first frame: not yet placed)
};

/// Two widgets of one frame with the same ID (the second loses its clicks).
struct Duplicate {
    uint32_t id = 0;
    std::string label;
    std::string window;
};

void set_enabled(bool on);
bool enabled();

/// Starts recording a new frame (draw_frame calls it first thing).
void begin_frame();
/// The widgets of the frame recorded since the last begin_frame(), in order.
const std::vector<Widget>& widgets();
/// IDs used twice or more in that frame.
const std::vector<Duplicate>& duplicates();

/// The label of the text field being typed into this frame ("" if none), for a
/// scripted test to know its keys will reach the field it clicked.
std::string active_text_field();

/// The text a user reads for a label: what stands before "##" ("Structure" for
/// "Structure###structure_type").
std::string visible_text(const std::string& label);

}  // namespace accelviz::widget_audit
