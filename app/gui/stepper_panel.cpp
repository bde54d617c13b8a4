#include "app/gui/stepper_panel.h"

#include <algorithm>
#include <numbers>
#include <cmath>
#include <cstdio>

#include <imgui.h>

#include "app/gui/camera_control.h"
#include "app/gui/session.h"
#include "core/accel/bsp_tree.h"
#include "core/traversal/event_json.h"

namespace accelviz {

namespace {

ImU32 im_colour(DebugColour c, uint8_t alpha = 255) { return IM_COL32(c.r, c.g, c.b, alpha); }
ImVec4 im_vec4(DebugColour c) { return ImVec4(c.r / 255.0f, c.g / 255.0f, c.b / 255.0f, 1.0f); }

/// "1.25", "inf", "-inf".
std::string number(float v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    if (std::isnan(v)) return "nan";
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", v);
    return text;
}

void grey_text(const char* text) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    ImGui::TextWrapped("%s", text);
    ImGui::PopStyleColor();
}

/// The t range a chart of intervals draws: every finite end given, padded by
/// `pad_fraction` of the range on each side (zoomed on the intervals, as the lecture
/// draws them), and where a t falls on a line `line_w` wide starting at `x0`.
struct TRange {
    float lo = 0.0f, hi = 0.0f;
    bool any = false;

    void include(float v) {
        if (!std::isfinite(v)) return;
        lo = any ? std::min(lo, v) : v;
        hi = any ? std::max(hi, v) : v;
        any = true;
    }
    void pad(float pad_fraction) {
        if (!any) include(0.0f);
        if (!(hi > lo)) hi = lo + std::max(std::abs(lo), 1.0f) * 0.1f;
        const float p = pad_fraction * (hi - lo);
        lo -= p;
        hi += p;
    }
    float x(float t, float x0, float line_w) const {
        if (std::isnan(t)) return x0;
        return x0 + std::clamp((t - lo) / (hi - lo), 0.0f, 1.0f) * line_w;
    }
};

/// The interval from x_a to x_b on the row at y: a bar `bar` high above and below the
/// line, or, for an empty interval (a > b), its ends crossed over, `cross` high.
void draw_interval(ImDrawList* draw, bool empty, float x_a, float x_b, float y, float bar, float cross, ImU32 colour) {
    if (!empty) {
        draw->AddRectFilled(ImVec2(x_a, y - bar), ImVec2(std::max(x_b, x_a + 2.0f), y + bar), colour);
    } else {
        draw->AddLine(ImVec2(x_b, y - cross), ImVec2(x_a, y + cross), colour, 2.0f);
        draw->AddLine(ImVec2(x_b, y + cross), ImVec2(x_a, y - cross), colour, 2.0f);
    }
}

}  // namespace

CameraParams stepper_side_view(const CameraParams& camera, const Ray& ray) {
    CameraParams side = camera;
    constexpr double kDegree = std::numbers::pi / 180.0;
    orbit(side, 35.0 * kDegree, 15.0 * kDegree);
    const Vec3d o{ray.origin.x, ray.origin.y, ray.origin.z}, d{ray.dir.x, ray.dir.y, ray.dir.z};
    const double dd = dot(d, d);
    if (!(dd > 0)) return side;
    const double t = std::max(0.0, dot(camera.target - o, d) / dd);
    const Vec3d focus = o + d * t;
    const Vec3d offset = side.eye - side.target;
    side.target = focus;
    side.eye = focus + offset * 0.6;
    if (validate(side)) return camera;  // a degenerate camera (e.g. eye on target) stays as it was
    return side;
}

void StepperPanel::pick(AppState& state, const CameraParams& camera, int width, int height, int x, int y) {
    if (width <= 0 || height <= 0) return;
    const Camera cam(camera, width, height);
    state.stepper.ray = cam.ray(x, y);
    state.stepper.any_hit = false;
    state.stepper.pixel = std::array<int, 2>{x, y};
    state.stepper.step = 0;
    state.stepper.open = true;
}

// [SECTION] Update

void StepperPanel::update(AppState& state, Session& session, double delta_seconds, bool wait) {
    // A compare build that has finished is taken even with the stepper closed: left
    // waiting, it would count as pending work for ever and the window would never go idle.
    if (compare_job.has_result()) {
        auto done = compare_job.take();
        if (done && session.scene && done->mesh == session.scene->mesh) {
            compare = std::move(*done);
            compare_ray_of.reset();
        }
    }
    if (!state.stepper.open || !session.scene) return;
    const bool new_scene = traced_scene != session.scene;
    const bool new_ray = state.stepper.ray.has_value() != traced_ray.has_value() ||
                         (state.stepper.ray && *state.stepper.ray != *traced_ray) ||
                         state.stepper.any_hit != traced_any_hit;
    if (new_scene || new_ray) {
        if (new_scene) boxes = NodeBoxes(*session.scene->accel);
        // Another pixel, a typed ray or another mesh: a new chain. (Another structure
        // keeps it: every structure gives the same hits, so the same secondary rays.)
        const bool new_mesh = !traced_scene || traced_scene->mesh != session.scene->mesh;
        if ((new_ray && !following) || new_mesh) earlier_rays.clear();
        following = false;
        traced_scene = session.scene;
        traced_ray = state.stepper.ray;
        traced_any_hit = state.stepper.any_hit;
        trace = state.stepper.ray ? record_ray(*session.scene->accel, *state.stepper.ray, query(state)) : SteppedRay{};
        shown_step = size_t(-1);
        playback.restart();
    }
    if (state.stepper.ray && (!edits_of || *edits_of != *state.stepper.ray)) {
        const Ray& r = *state.stepper.ray;
        for (int a = 0; a < 3; ++a) {
            origin_edit[a] = r.origin[a];
            dir_edit[a] = r.dir[a];
        }
        edits_of = r;
    }

    // Playback: `speed` events per second (the window only).
    const size_t end = trace.events.size();
    if (!wait) playback.advance(state.stepper.step, end, delta_seconds);
    const size_t step = std::min(state.stepper.step, end);
    if (step != shown_step) {
        step_state = replay(trace.events, step);
        shown_step = step;
        geometry = state.stepper.ray ? step_geometry(trace, step_state, boxes, *session.scene->mesh) : DebugGeometry{};
        geometry_dirty = true;
    }

    // The compare table: structures per mesh on the worker, rows per ray (cheap).
    if (compare_requested != session.scene->mesh) {
        compare_requested = session.scene->mesh;
        compare.reset();
        compare_rows.clear();
        compare_ray_of.reset();
        std::shared_ptr<const Mesh> mesh = session.scene->mesh;
        compare_job.submit([mesh] {
            CompareBuild out;
            out.mesh = mesh;
            auto set = build_compare_set(*mesh);
            if (set) out.set = std::make_shared<const CompareSet>(std::move(*set));
            else out.error = set.error();
            return out;
        });
    }
    if (wait && !compare) {
        compare_job.wait();
        if (auto done = compare_job.take(); done && done->mesh == session.scene->mesh) compare = std::move(*done);
    }
    if (compare && compare->set && state.stepper.ray &&
        (!compare_ray_of || *compare_ray_of != *state.stepper.ray || compare_any_hit_of != state.stepper.any_hit)) {
        compare_rows = compare_ray(*compare->set, *state.stepper.ray, query(state));
        compare_ray_of = state.stepper.ray;
        compare_any_hit_of = state.stepper.any_hit;
    }
}

void StepperPanel::handle_keys(AppState& state) {
    if (state.stepper.open && traced_ray) playback.handle_keys(state.stepper.step, trace.events.size());
}

// [SECTION] The panel

/// The lecture's picture: three number lines with each slab's interval, the
/// intersection below them, and the verdict.
/// The box tests of one node's children side by side, one row each on a common t axis:
/// what a wide BVH's SIMD instructions compute at once (4 or 8 boxes), or algorithm
/// 2's two children. The row of the event being shown is marked.
void StepperPanel::draw_sibling_tests(const SiblingTests& run, size_t current) const {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::Text("Tested together: %zu child boxes of one node", run.size());
    ImGui::TextDisabled(run.size() > 2 ? "A wide BVH node: its children's slab tests are one sequence of SIMD "
                                         "instructions, one box per lane; the walk then visits the entered ones "
                                         "nearest first."
                                       : "Algorithm 2 tests both children's boxes, then visits the nearer one first.");
    ImGui::PopTextWrapPos();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const float font = ImGui::GetFontSize();
    const float width = ImGui::GetContentRegionAvail().x;
    const float label_w = 4.5f * font;
    const float line_w = std::max(width - label_w - 0.5f * font, 4.0f * font);
    const float row_h = 1.4f * font;
    TRange range;
    for (size_t i = run.first; i < run.last; ++i) {
        range.include(trace.events[i].t_enter);
        range.include(trace.events[i].t_exit);
    }
    range.pad(0.05f);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    auto x_of = [&](float t) { return range.x(t, origin.x + label_w, line_w); };
    const ImU32 text = ImGui::GetColorU32(ImGuiCol_Text);
    const ImU32 faint = ImGui::GetColorU32(ImGuiCol_TextDisabled);
    for (size_t i = run.first; i < run.last; ++i) {
        const TraversalEvent& e = trace.events[i];
        const float y = origin.y + float(i - run.first) * row_h + 0.6f * font;
        char label[32];
        std::snprintf(label, sizeof label, "%s%u", i == current ? "> " : "  ", e.node);
        draw->AddText(ImVec2(origin.x, y - 0.5f * font), i == current ? text : faint, label);
        draw->AddLine(ImVec2(origin.x + label_w, y), ImVec2(origin.x + label_w + line_w, y), faint, 1.0f);
        const ImU32 colour = e.hit ? im_colour(kStepColours.tested_hit) : im_colour(kStepColours.tested_miss);
        draw_interval(draw, !(e.t_enter <= e.t_exit), x_of(e.t_enter), x_of(e.t_exit), y, 0.3f * font, 0.3f * font,
                      colour);
    }
    ImGui::Dummy(ImVec2(width, float(run.size()) * row_h));
    ImGui::TextDisabled("t from %s to %s; this box's slabs:", number(range.lo).c_str(), number(range.hi).c_str());
}

void StepperPanel::draw_slab_inspector(const SlabInspection& s) const {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const float font = ImGui::GetFontSize();
    const float width = ImGui::GetContentRegionAvail().x;
    const float label_w = 2.0f * font;
    const float line_w = std::max(width - label_w - 0.5f * font, 4.0f * font);
    const float row_h = 2.2f * font;
    // The t range drawn: every finite end of the three slabs and of their intersection.
    TRange range;
    for (int a = 0; a < 3; ++a) {
        range.include(s.axis_min[a]);
        range.include(s.axis_max[a]);
    }
    range.include(s.t_enter);
    range.include(s.t_exit);
    range.pad(0.08f);
    const float lo = range.lo, hi = range.hi;
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    auto x_of = [&](float t) { return range.x(t, origin.x + label_w, line_w); };
    const ImU32 text = ImGui::GetColorU32(ImGuiCol_Text);
    const ImU32 faint = ImGui::GetColorU32(ImGuiCol_TextDisabled);
    // Per-axis colours apart from the verdict's green (entered) and red (missed).
    const ImU32 axis_colours[3] = {IM_COL32(220, 140, 60, 255), IM_COL32(185, 120, 235, 255),
                                   IM_COL32(90, 150, 255, 255)};
    const char* names[4] = {"x", "y", "z", "all"};
    for (int row = 0; row < 4; ++row) {
        const float y = origin.y + row * row_h + 0.6f * font;
        draw->AddText(ImVec2(origin.x, y - 0.5f * font), text, names[row]);
        draw->AddLine(ImVec2(origin.x + label_w, y), ImVec2(origin.x + label_w + line_w, y), faint, 1.0f);
        float a = 0, b = 0;
        ImU32 colour;
        if (row < 3) {
            a = s.axis_min[row];
            b = s.axis_max[row];
            colour = axis_colours[row];
        } else {
            a = s.t_enter;
            b = s.t_exit;
            colour = s.hit ? im_colour(kStepColours.tested_hit) : im_colour(kStepColours.tested_miss);
        }
        const bool empty = !(a <= b);
        draw_interval(draw, empty, x_of(a), x_of(b), y, 0.3f * font, 0.35f * font, colour);
        if (!empty && std::isinf(b)) draw->AddText(ImVec2(x_of(b) - font, y - 1.3f * font), colour, "->");
        if (!empty && std::isinf(a)) draw->AddText(ImVec2(x_of(a), y - 1.3f * font), colour, "<-");
        char numbers[96];
        std::snprintf(numbers, sizeof numbers, "[%s, %s]", number(a).c_str(), number(b).c_str());
        draw->AddText(ImVec2(origin.x + label_w, y + 0.35f * font), text, numbers);
    }
    // The ray's start (t = 0) as a tick on every line, when it is in the range drawn.
    const float t0 = std::max(s.ray_min, 0.0f);
    if (t0 >= lo && t0 <= hi) {
        const float x0 = x_of(t0);
        draw->AddLine(ImVec2(x0, origin.y), ImVec2(x0, origin.y + 4 * row_h - 0.2f * font), faint, 1.0f);
    }
    ImGui::Dummy(ImVec2(width, 4 * row_h));
    ImGui::PushStyleColor(ImGuiCol_Text, s.hit ? im_vec4(kStepColours.tested_hit) : im_vec4(kStepColours.tested_miss));
    ImGui::TextWrapped("%s", s.verdict.c_str());
    ImGui::PopStyleColor();
    if (s.widened) grey_text("BVH: each plane distance moved outwards by 2^-16 (core/math/box_test.h)");
}

void StepperPanel::draw_compare() {
    if (!compare) {
        grey_text("building naive, BVH, grid, KD tree and octree ...");
        return;
    }
    if (!compare->error.empty()) {
        ImGui::TextWrapped("compare: %s", compare->error.c_str());
        return;
    }
    if (compare_rows.empty()) return;
    const ImGuiTableFlags flags = ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit;
    if (ImGui::BeginTable("##compare", 6, flags)) {
        ImGui::TableSetupColumn("structure");
        ImGui::TableSetupColumn("nodes");
        ImGui::TableSetupColumn("boxes");
        ImGui::TableSetupColumn("tris");
        ImGui::TableSetupColumn("mbox");
        ImGui::TableSetupColumn("result");
        ImGui::TableHeadersRow();
        for (const CompareRow& row : compare_rows) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(row.label.c_str());
            ImGui::TableNextColumn();
            ImGui::Text("%llu", (unsigned long long)row.counters.nodes_visited);
            ImGui::TableNextColumn();
            ImGui::Text("%llu", (unsigned long long)row.counters.box_tests);
            ImGui::TableNextColumn();
            ImGui::Text("%llu", (unsigned long long)row.counters.triangle_tests);
            ImGui::TableNextColumn();
            ImGui::Text("%llu", (unsigned long long)row.counters.mailbox_skips);
            ImGui::TableNextColumn();
            if (compare_any_hit_of)
                ImGui::Text("%s%s", row.blocked ? "blocked" : "free", row.agrees_with_naive ? "" : " (differs!)");
            else if (row.hit.found())
                ImGui::Text("%u, t=%.4g%s", row.hit.tri, row.hit.t, row.agrees_with_naive ? "" : " (differs!)");
            else
                ImGui::TextUnformatted("miss");
        }
        ImGui::EndTable();
    }
}

void StepperPanel::draw_ray_fields(AppState& state, Session& session) {
    const float font = ImGui::GetFontSize();
    ImGui::SetNextItemWidth(-5.0f * font);
    ImGui::InputFloat3("origin", origin_edit, "%.4g");
    ImGui::SetNextItemWidth(-5.0f * font);
    ImGui::InputFloat3("direction", dir_edit, "%.4g");
    if (ImGui::Button("Trace this ray")) {
        const Vec3 d(dir_edit[0], dir_edit[1], dir_edit[2]);
        const Vec3 o(origin_edit[0], origin_edit[1], origin_edit[2]);
        if (!(d.x != 0 || d.y != 0 || d.z != 0) || !std::isfinite(d.x + d.y + d.z) || !std::isfinite(o.x + o.y + o.z)) {
            session.notify("Stepper: the origin must be finite and the direction a finite, non-zero vector", true);
        } else {
            Ray r;
            r.origin = o;
            r.dir = d;
            state.stepper.ray = r;
            state.stepper.any_hit = false;
            state.stepper.pixel.reset();
            state.stepper.step = 0;
        }
    }
}

void StepperPanel::draw(AppState& state, Session& session, bool lecture) {
    const std::string structure = session.scene ? std::string(to_string(session.scene->accel_config.type)) : "?";
    const char* kind = state.stepper.any_hit ? "shadow ray" : earlier_rays.empty() ? "ray" : "reflection ray";
    char what[160];
    if (state.stepper.pixel)
        std::snprintf(what, sizeof what, "%s, %s of pixel (%d, %d)", structure.c_str(), kind,
                      (*state.stepper.pixel)[0], (*state.stepper.pixel)[1]);
    else
        std::snprintf(what, sizeof what, "%s, %s", structure.c_str(), kind);
    // "Stepper: what" and Close on one line; in a narrow panel, what goes below them.
    const float close_width = ImGui::CalcTextSize("Close").x + 2.0f * ImGui::GetStyle().FramePadding.x;
    const std::string title = std::string("Stepper: ") + what;
    const bool one_line = ImGui::CalcTextSize(title.c_str()).x + ImGui::GetStyle().ItemSpacing.x + close_width <=
                          ImGui::GetContentRegionAvail().x;
    ImGui::TextUnformatted(one_line ? title.c_str() : "Stepper");
    ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - close_width);
    if (ImGui::SmallButton("Close")) {
        state.stepper.open = false;
        playback.playing = false;
    }
    if (!one_line) ImGui::TextWrapped("%s", what);
    if (!lecture || !state.stepper.ray) {
        const bool typing =
            ImGui::CollapsingHeader("Type a ray", state.stepper.ray ? 0 : ImGuiTreeNodeFlags_DefaultOpen);
        if (typing) draw_ray_fields(state, session);
    }
    if (!state.stepper.ray) {
        grey_text("Click a pixel in the 3D view (or in the ray-cast half of the split view) to pick its ray, "
                  "or type an origin and a direction.");
        return;
    }

    playback.draw_buttons(state.stepper.step, trace.events.size());
    const size_t end = trace.events.size();
    const size_t step = std::min(state.stepper.step, end);
    ImGui::Text("step %zu of %zu", step, end);
    ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - ImGui::CalcTextSize("View from the side").x -
                    2.0f * ImGui::GetStyle().FramePadding.x);
    if (ImGui::SmallButton("View from the side") && state.camera)
        state.camera = stepper_side_view(*state.camera, *state.stepper.ray);
    draw_next_rays(state, session);
    if (const TraversalEvent* e = event_before(trace, step)) {
        // (The state after the event has the closest hit it was compared with: no event changes both.)
        ImGui::PushStyleColor(ImGuiCol_Text, im_vec4(kStepColours.interval));
        ImGui::TextWrapped("%s", explain_event(*e, step_state).c_str());
        ImGui::PopStyleColor();
    } else {
        grey_text("before the first event: press Right (or >) to step");
    }
    playback.draw_event_list(trace.events, state.stepper.step, lecture ? 3 : 7,
                             [](const TraversalEvent& e) { return describe(e); });

    // Counters next to the naive O(N) count.
    const Counters& c = step_state.counters;
    const size_t triangles = session.scene ? session.scene->mesh->triangle_count() : 0;
    ImGui::Text("visited %llu   box tests %llu", (unsigned long long)c.nodes_visited, (unsigned long long)c.box_tests);
    ImGui::Text("triangle tests %llu of naive %zu   mailbox skips %llu", (unsigned long long)c.triangle_tests,
                triangles, (unsigned long long)c.mailbox_skips);
    if (trace.query == StopAt::AnyHit) {
        // The any-hit query keeps no nearest hit: the first triangle hit blocks the segment.
        const auto blocker = std::find_if(step_state.tested.begin(), step_state.tested.end(),
                                          [](const StepState::TestedTriangle& t) { return t.hit; });
        if (blocker != step_state.tested.end())
            ImGui::TextColored(im_vec4(kStepColours.closest), "blocked by triangle %u at t = %.5g: in shadow",
                               blocker->tri, blocker->t);
        else
            ImGui::TextDisabled(step_state.done ? "nothing in the way: the light is seen" : "blocked: not yet");
    } else if (step_state.closest.found()) {
        ImGui::TextColored(im_vec4(kStepColours.closest), "closest so far: triangle %u, t = %.5g",
                           step_state.closest.tri, step_state.closest.t);
    } else {
        ImGui::TextDisabled("closest so far: none");
    }

    // What explains the current event comes first: its inspector, or at the end the comparison.
    const TraversalEvent* current = event_before(trace, step);
    if (current && current->kind == EventKind::Done) {
        if (ImGui::CollapsingHeader("Compare structures", ImGuiTreeNodeFlags_DefaultOpen)) draw_compare();
        draw_stack();
        draw_inspectors(current);
    } else {
        draw_inspectors(current);
        draw_stack();
        if (ImGui::CollapsingHeader("Compare structures", ImGuiTreeNodeFlags_DefaultOpen)) draw_compare();
    }
    if (ImGui::CollapsingHeader("Colours")) {
        const StepColours& k = kStepColours;
        const std::pair<const char*, DebugColour> legend[] = {
            {"current node / interval", k.current}, {"box tested: entered", k.tested_hit},
            {"box tested: missed", k.tested_miss},  {"on the stack", k.stacked},
            {"visited", k.visited},                 {"culled: missed", k.culled_missed},
            {"culled: beyond closest", k.culled_beyond}, {"triangle hit", k.triangle_hit},
            {"triangle missed", k.triangle_miss},   {"closest hit", k.closest},
            {"hit outside cell", k.rejected},       {"split plane", k.split}};
        for (const auto& [name, colour] : legend) ImGui::TextColored(im_vec4(colour), "%s", name);
    }
}

StopAt StepperPanel::query(const AppState& state) { return state.stepper.any_hit ? StopAt::AnyHit : StopAt::ClosestHit; }

void StepperPanel::draw_next_rays(AppState& state, const Session& session) {
    // A shadow ray: the any-hit query, which may stop at the first triangle in the way.
    if (state.stepper.any_hit)
        grey_text("Shadow ray, from the hit to the light (t = 1): any hit blocks it, so the walk stops at the "
                  "first triangle in the way, without looking for the nearest.");
    // The rays the ray caster traces from this hit, stepped by the same code: the
    // shadow ray to the light and, off a mirror, the reflection ray.
    const LoadedScene* scene = session.scene.get();
    const bool camera_or_reflection = !state.stepper.any_hit;
    if (scene && trace.hit.found() && camera_or_reflection && state.light.point_light() &&
        trace.hit.tri < scene->mesh->triangle_count()) {
        const Triangle tri = scene->mesh->triangle(trace.hit.tri);
        const Ray& ray = *state.stepper.ray;
        auto follow = [&](const Ray& next, bool any_hit) {
            following = true;
            earlier_rays.push_back(state.stepper);
            state.stepper.ray = next;
            state.stepper.any_hit = any_hit;
            state.stepper.step = 0;
            playback.playing = false;
        };
        const Vec3 light = to_float(light_position(state.light, scene->bounds));
        const bool mirror = state.light.reflections && trace.hit.tri < scene->mesh->mirror.size() &&
                            scene->mesh->mirror[trace.hit.tri] != 0;
        if (mirror && earlier_rays.empty()) {
            if (ImGui::Button("Step its reflection ray")) follow(reflection_ray(tri, trace.hit.u, trace.hit.v, ray.dir), false);
        } else if (!state.light.shadows) {
        } else if (auto to_light = shadow_ray(tri, trace.hit.u, trace.hit.v, ray.dir, light)) {
            if (ImGui::Button("Step its shadow ray")) follow(*to_light, true);
        } else {
            grey_text("the light is behind this surface: no shadow ray (unlit)");
        }
    }
    if (!earlier_rays.empty()) {
        if (camera_or_reflection && trace.hit.found() && state.light.point_light()) ImGui::SameLine();
        if (ImGui::Button("Back to the ray before")) {
            state.stepper = earlier_rays.back();
            earlier_rays.pop_back();
            following = true;
            playback.playing = false;
        }
    }
}

void StepperPanel::draw_stack() {
    if (!ImGui::CollapsingHeader("Stack", ImGuiTreeNodeFlags_DefaultOpen)) return;
    if (step_state.stack.empty()) ImGui::TextDisabled("(empty)");
    for (size_t i = step_state.stack.size(); i-- > 0;) {
        const auto& x = step_state.stack[i];
        ImGui::TextColored(im_vec4(kStepColours.stacked), "%s node %u   t_enter %s",
                           i + 1 == step_state.stack.size() ? "top" : "   ", x.node, number(x.t_enter).c_str());
    }
}

/// The inspectors, the one of the current event's kind first.
void StepperPanel::draw_inspectors(const TraversalEvent* current) {
    const size_t step = std::min(step_state.steps, trace.events.size());
    auto slab = [&] {
        if (!step_state.last_box_test || !ImGui::CollapsingHeader("Slab inspector", ImGuiTreeNodeFlags_DefaultOpen))
            return;
        const bool now = current && current->kind == EventKind::BoxTest;
        ImGui::Text("%s box test, node %u", now ? "this" : "last", step_state.last_box_test->node);
        // The boxes tested together with it first (a wide node's lanes), then its own slabs.
        for (size_t i = step; i-- > 0;)
            if (trace.events[i].kind == EventKind::BoxTest) {
                const SiblingTests run = sibling_box_tests(trace.events, i);
                if (run.size() >= 2) draw_sibling_tests(run, i);
                break;
            }
        // Why the boxes are axis-aligned: this ray's box tests so far, counted both ways.
        const uint64_t box_tests = uint64_t(std::count_if(trace.events.begin(), trace.events.begin() + long(step),
                                                          [](const TraversalEvent& e) { return e.kind == EventKind::BoxTest; }));
        const BoxTestOps axis = box_test_ops(box_tests, kAxisPlaneOps);
        const BoxTestOps general = box_test_ops(box_tests, kGeneralPlaneOps);
        ImGui::PushTextWrapPos(0.0f);
        ImGui::Text("%llu box tests so far, 6 planes each: %lld +-, %lld / (axis-aligned) against %lld x, %lld +-, "
                    "%lld / (general planes)",
                    (unsigned long long)box_tests, (long long)axis.adds, (long long)axis.divides,
                    (long long)general.multiplies, (long long)general.adds, (long long)general.divides);
        ImGui::TextDisabled("A plane crossing: axis-aligned x = x0, t = (x0 - o.x) / d.x: 1 -, 1 /; general N.x = c, "
                            "t = (c - N.o) / (N.d): 6 x, 5 +-, 1 /.");
        ImGui::PopTextWrapPos();
        if (auto s = inspect_box_test(trace, boxes, *step_state.last_box_test)) draw_slab_inspector(*s);
    };
    auto triangle = [&] {
        if (!step_state.last_triangle_test ||
            !ImGui::CollapsingHeader("Triangle inspector", ImGuiTreeNodeFlags_DefaultOpen))
            return;
        size_t index = 0;
        for (size_t i = step; i-- > 0;)
            if (trace.events[i].kind == EventKind::TriangleTest) {
                index = i;
                break;
            }
        const TriangleInspection t = inspect_triangle_test(trace, index);
        const bool now = current && current->kind == EventKind::TriangleTest;
        ImGui::Text("%s triangle test: triangle %u", now ? "this" : "last", t.tri);
        ImGui::Text("u = %s   v = %s   1-u-v = %s", number(t.u).c_str(), number(t.v).c_str(), number(t.w).c_str());
        ImGui::Text("t = %s   accepted range [%s, %s]", number(t.t).c_str(), number(trace.ray.t_min).c_str(),
                    number(t.t_max).c_str());
        ImGui::PushStyleColor(ImGuiCol_Text,
                              t.hit ? im_vec4(kStepColours.triangle_hit) : im_vec4(kStepColours.tested_miss));
        ImGui::TextWrapped("%s", t.verdict.c_str());
        ImGui::PopStyleColor();
        // Both tests on this triangle: the one that ran, and the other.
        if (!traced_scene) return;
        const TriangleTestComparison both = compare_triangle_tests(trace, t, *traced_scene->mesh);
        auto line = [&](const char* name, TriangleTestKind kind, const TriangleTest& r) {
            const bool ran = trace.triangle_test == kind;
            ImGui::TextColored(r.hit ? im_vec4(kStepColours.triangle_hit) : im_vec4(kStepColours.tested_miss),
                               "%s%s: %s  (u %s, v %s)", name, ran ? " (ran)" : "", r.hit ? "hit" : "miss",
                               number(r.u).c_str(), number(r.v).c_str());
        };
        line("Moller-Trumbore", TriangleTestKind::MollerTrumbore, both.moller_trumbore);
        line("watertight", TriangleTestKind::Watertight, both.watertight);
        if (both.disagree())
            ImGui::TextWrapped("The two tests disagree: the ray passes within rounding of an edge or a vertex. "
                               "Structure > Triangle test picks the one that runs.");
        draw_plane_first(t);
    };
    auto split = [&] {
        if (!step_state.last_split || !ImGui::CollapsingHeader("Split plane", ImGuiTreeNodeFlags_DefaultOpen)) return;
        const TraversalEvent& e = *step_state.last_split;
        if (e.axis == kGeneralPlane) {  // a BSP node: a plane facing any way
            const Vec3 n = boxes.plane_normal(e.node);
            ImGui::Text("node %u: plane N.p = %s, N = (%s, %s, %s)", e.node, number(e.split).c_str(),
                        number(n.x).c_str(), number(n.y).c_str(), number(n.z).c_str());
            ImGui::Text("t_split = (c - N.o) / (N.d) = %s, near side: %s", number(e.t).c_str(),
                        e.near_first ? "back" : "front");
            return;
        }
        const char* axis = e.axis == 0 ? "x" : e.axis == 1 ? "y" : "z";
        ImGui::Text("node %u: %s = %s", e.node, axis, number(e.split).c_str());
        ImGui::Text("t_split = %s, near side: %s", number(e.t).c_str(), e.near_first ? "lower" : "upper");
    };
    auto cells = [&] {
        if (step_state.cells.empty() || !boxes.is_grid() ||
            !ImGui::CollapsingHeader("Cells walked", ImGuiTreeNodeFlags_DefaultOpen))
            return;
        const size_t n = step_state.cells.size();
        for (size_t i = n > 6 ? n - 6 : 0; i < n; ++i) {
            const TraversalEvent& e = step_state.cells[i];
            ImGui::Text("(%d, %d, %d)  t_in %s  t_out %s", e.cell[0], e.cell[1], e.cell[2], number(e.t_enter).c_str(),
                        number(e.t_exit).c_str());
        }
        if (n > 6) ImGui::TextDisabled("(%zu earlier)", n - 6);
    };
    auto rejected = [&] {
        if (step_state.rejected.empty() ||
            !ImGui::CollapsingHeader("Hits outside the cell", ImGuiTreeNodeFlags_DefaultOpen))
            return;
        for (const TraversalEvent& e : step_state.rejected)
            ImGui::TextColored(im_vec4(kStepColours.rejected), "triangle %u at t = %s > cell end %s", e.tri,
                               number(e.t).c_str(), number(e.t_exit).c_str());
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        ImGui::TextWrapped("A hit beyond the current cell may hide behind a closer triangle of a later cell: it "
                           "counts only once the walk reaches the cell that holds it.");
        ImGui::PopStyleColor();
    };
    const EventKind kind = current ? current->kind : EventKind::Done;
    if (kind == EventKind::HitOutsideCell) rejected();
    if (kind == EventKind::TriangleTest || kind == EventKind::NewClosest || kind == EventKind::MailboxSkip) triangle();
    if (kind == EventKind::SplitPlane) split();
    if (kind == EventKind::EnterCell) cells();
    slab();
    if (!(kind == EventKind::TriangleTest || kind == EventKind::NewClosest || kind == EventKind::MailboxSkip)) triangle();
    if (kind != EventKind::SplitPlane) split();
    if (kind != EventKind::EnterCell) cells();
    if (kind != EventKind::HitOutsideCell) rejected();
}

/// The lecture's first way on the inspected triangle and ray, beside Möller–Trumbore's
/// u, v, t: the plane's t and point, the three edge tests, and what each way costs.
void StepperPanel::draw_plane_first(const TriangleInspection& t) const {
    if (!traced_scene || t.tri >= traced_scene->mesh->triangle_count() ||
        !ImGui::TreeNodeEx("The lecture's two ways", ImGuiTreeNodeFlags_DefaultOpen))
        return;
    Ray ray = trace.ray;
    ray.t_max = t.t_max;
    const PlaneFirstTest p = plane_first_test(traced_scene->mesh->triangle(t.tri), ray);
    if (p.parallel) {
        ImGui::TextWrapped("1. Plane first: N·d = 0, the ray runs along the plane: no point to test.");
    } else {
        ImGui::TextWrapped("1. Plane first: t = N·(p0 - o) / N·d = %s, x = (%s, %s, %s)", number(p.t).c_str(),
                           number(p.point.x).c_str(), number(p.point.y).c_str(), number(p.point.z).c_str());
        const char* edge_names[3] = {"p0-p1", "p1-p2", "p2-p0"};
        std::string edges = "   edges:";
        for (int i = 0; i < 3; ++i)
            edges += std::string(i ? ",  " : " ") + edge_names[i] + (p.edge[i] >= 0.0f ? " in" : " OUT");
        ImGui::TextUnformatted(edges.c_str());
        ImGui::TextColored(p.hit ? im_vec4(kStepColours.triangle_hit) : im_vec4(kStepColours.tested_miss), "   %s",
                           p.hit ? "inside all three edges, t in range: hit"
                           : !p.inside ? "outside an edge: miss"
                                       : "inside, but t out of range: miss");
    }
    ImGui::TextWrapped("2. Moller-Trumbore: [t u v] = M^-1 (o - p0) at once: t = %s, u = %s, v = %s",
                       number(t.t).c_str(), number(t.u).c_str(), number(t.v).c_str());
    ImGui::TextDisabled("cost per test: 1. %d x, %d +-, %d /   2. %d x, %d +-, %d /", kPlaneFirstOps.multiplies,
                        kPlaneFirstOps.adds, kPlaneFirstOps.divides, kMollerTrumboreOps.multiplies,
                        kMollerTrumboreOps.adds, kMollerTrumboreOps.divides);
    ImGui::TreePop();
}

// [SECTION] 3D view

void StepperPanel::draw_3d(Renderer& renderer, float line_width) {
    if (traced_ray) gl_geometry.draw(renderer, geometry, geometry_dirty, line_width);
}

void StepperPanel::draw_labels(const View3D& view) const {
    if (traced_ray) draw_debug_labels(geometry.labels, view);
}

}  // namespace accelviz
