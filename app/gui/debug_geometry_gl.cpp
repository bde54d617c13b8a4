#include "app/gui/debug_geometry_gl.h"

#include <algorithm>

#include <imgui.h>

namespace accelviz {

namespace {

Rgba8 rgba(DebugColour c) { return {c.r, c.g, c.b, c.a}; }
ImU32 im_colour(DebugColour c) { return IM_COL32(c.r, c.g, c.b, 255); }

}  // namespace

void DebugGeometryGl::draw(Renderer& renderer, const DebugGeometry& g, bool& dirty, float line_width) {
    if (dirty) {
        if (!boxes_) boxes_ = std::make_unique<BoxBuffer>();
        if (!segments_) segments_ = std::make_unique<ColouredBuffer>();
        if (!quads_) quads_ = std::make_unique<ColouredBuffer>();
        std::vector<BoxInstance> boxes_out;
        for (const DebugBox& b : g.boxes) boxes_out.push_back({b.box.lo, b.box.hi, rgba(b.colour)});
        std::vector<ColouredVertex> ends;
        for (const DebugSegment& s : g.segments) {
            ends.push_back({s.a, rgba(s.colour)});
            ends.push_back({s.b, rgba(s.colour)});
        }
        std::vector<ColouredQuad> quads;
        for (const DebugQuad& q : g.quads)
            quads.push_back({{q.corners[0], q.corners[1], q.corners[2], q.corners[3]}, rgba(q.colour)});
        for (const DebugTriangle& t : g.triangles) quads.push_back({{t.p[0], t.p[1], t.p[2], t.p[2]}, rgba(t.colour)});
        boxes_->upload(boxes_out);
        segments_->upload_segments(ends);
        quads_->upload_quads(quads);
        dirty = false;
    }
    renderer.draw_quads(*quads_);
    renderer.set_line_width(line_width);
    renderer.draw_boxes(*boxes_);
    renderer.set_line_width(std::min(2.5f * line_width, 8.0f));
    renderer.draw_segments(*segments_);
    renderer.set_line_width(line_width);
}

void draw_debug_labels(const std::vector<DebugLabel>& labels, const View3D& view) {
    if (view.rect.empty()) return;
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    const auto& m = view.view_projection;
    const ImU32 shadow = IM_COL32(0, 0, 0, 200);
    std::vector<ImVec4> placed;  // (x0, y0, x1, y1) of the labels drawn: later ones move down to clear them
    for (const DebugLabel& label : labels) {
        const Vec3 p = label.at;
        const float x = m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12];
        const float y = m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13];
        const float w = m[3] * p.x + m[7] * p.y + m[11] * p.z + m[15];
        if (!(w > 0.0f)) continue;
        const float sx = float(view.rect.x) + (0.5f * x / w + 0.5f) * float(view.rect.width);
        const float sy = float(view.rect.y) + (0.5f - 0.5f * y / w) * float(view.rect.height);
        if (!view.rect.contains(sx, sy)) continue;
        ImVec2 at(sx + 6.0f, sy - ImGui::GetFontSize() - 2.0f);
        const ImVec2 size = ImGui::CalcTextSize(label.text.c_str());
        for (int tries = 0; tries < 8; ++tries) {
            bool clear = true;
            for (const ImVec4& r : placed)
                if (at.x < r.z && at.x + size.x > r.x && at.y < r.w && at.y + size.y > r.y) {
                    at.y = r.w + 1.0f;
                    clear = false;
                }
            if (clear) break;
        }
        placed.push_back(ImVec4(at.x, at.y, at.x + size.x, at.y + size.y));
        draw->AddText(ImVec2(at.x + 1, at.y + 1), shadow, label.text.c_str());
        draw->AddText(at, im_colour(label.colour), label.text.c_str());
    }
}

}  // namespace accelviz
