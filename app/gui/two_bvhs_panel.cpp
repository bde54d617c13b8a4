#include "app/gui/two_bvhs_panel.h"

#include <algorithm>
#include <cstdio>

#include <imgui.h>

#include "app/gui/panel_widgets.h"

#include "core/accel/memory_budget.h"
#include "core/render/colormap.h"

namespace accelviz {

namespace {

/// Drawing more boxes than this (as whole levels, shallow first) would make a
/// big scene's panel slow and unreadable; the panel says which levels it shows.
constexpr size_t kMaxBoxesDrawn = 600;
/// Triangles filled in a picture at most (a scan's are finer than a pixel anyway).
constexpr uint64_t kMaxTrianglesDrawn = 20000;

constexpr ImU32 kCanvasBg = IM_COL32(24, 26, 32, 255);
constexpr ImU32 kCanvasFrame = IM_COL32(110, 110, 120, 255);
constexpr ImU32 kBetter = IM_COL32(120, 230, 120, 255);
/// Triangles by leaf: neighbouring leaves get different colours.
constexpr ImU32 kLeafColours[] = {IM_COL32(230, 120, 110, 210), IM_COL32(120, 170, 240, 210),
                                  IM_COL32(240, 200, 100, 210), IM_COL32(160, 220, 140, 210),
                                  IM_COL32(210, 140, 230, 210), IM_COL32(120, 220, 220, 210),
                                  IM_COL32(240, 160, 200, 210), IM_COL32(200, 200, 200, 210)};

ImU32 depth_colour(uint32_t depth, uint32_t deepest) {
    // From 0.2 up: the map's darkest purple would vanish into the background.
    const Rgb c = colormap(0.2 + 0.8 * (deepest == 0 ? 0.0 : double(depth) / double(deepest)));
    return IM_COL32(c.r, c.g, c.b, 255);
}

/// The node indices to draw: whole levels from the root down while they fit
/// kMaxBoxesDrawn, shallow first (deeper boxes are drawn over their parents).
std::vector<uint32_t> boxes_to_draw(const BvhTreeSummary& tree, uint32_t& deepest_drawn) {
    std::vector<size_t> per_level;
    for (const auto& box : tree.boxes) {
        if (box.depth >= per_level.size()) per_level.resize(box.depth + 1, 0);
        ++per_level[box.depth];
    }
    size_t total = 0;
    deepest_drawn = 0;
    for (size_t d = 0; d < per_level.size(); ++d) {
        if (d > 0 && total + per_level[d] > kMaxBoxesDrawn) break;
        total += per_level[d];
        deepest_drawn = uint32_t(d);
    }
    std::vector<uint32_t> out;
    out.reserve(total);
    for (uint32_t d = 0; d <= deepest_drawn; ++d)
        for (uint32_t i = 0; i < tree.boxes.size(); ++i)
            if (tree.boxes[i].depth == d) out.push_back(i);
    return out;
}

/// Sets the result's crop: the scene's box in the image, 5% wider each way, clamped to it.
template <class Result>
void crop_to_scene(Result& result, const Camera& camera, const Aabb& bounds) {
    const double w = camera.width(), h = camera.height();
    result.crop_x0 = 0, result.crop_y0 = 0, result.crop_x1 = w, result.crop_y1 = h;
    if (bounds.empty()) return;
    double x0 = w, y0 = h, x1 = 0, y1 = 0;
    for (int k = 0; k < 8; ++k) {
        const Vec3d p{k & 1 ? bounds.hi.x : bounds.lo.x, k & 2 ? bounds.hi.y : bounds.lo.y,
                      k & 4 ? bounds.hi.z : bounds.lo.z};
        const Camera::ImagePoint q = camera.project(p);
        if (!(q.depth > 0)) return;
        x0 = std::min(x0, q.x), x1 = std::max(x1, q.x), y0 = std::min(y0, q.y), y1 = std::max(y1, q.y);
    }
    const double margin = 0.05 * std::max(x1 - x0, y1 - y0);
    x0 = std::max(0.0, x0 - margin), y0 = std::max(0.0, y0 - margin);
    x1 = std::min(w, x1 + margin), y1 = std::min(h, y1 + margin);
    if (x1 - x0 < 1 || y1 - y0 < 1) return;  // off screen: the whole view
    result.crop_x0 = x0, result.crop_y0 = y0, result.crop_x1 = x1, result.crop_y1 = y1;
}

bool builder_combo(const char* label, BvhBuilder& value) {
    bool changed = false;
    if (ImGui::BeginCombo(label, std::string(to_string(value)).c_str())) {
        for (const std::string& name : bvh_builder_names()) {
            const BvhBuilder b = *parse_bvh_builder(name);
            if (ImGui::Selectable(name.c_str(), b == value) && b != value) {
                value = b;
                changed = true;
            }
        }
        ImGui::EndCombo();
    }
    return changed;
}

}  // namespace

TwoBvhsPanel::~TwoBvhsPanel() {
    if (progress_) progress_->cancel();
}

void TwoBvhsPanel::start(const Key& key, std::shared_ptr<const LoadedScene> scene) {
    if (progress_) progress_->cancel();  // an older measurement still running is not wanted
    requested_ = key;
    requested_mesh_ = scene->mesh;
    error_.clear();
    progress_ = std::make_shared<WorkProgress>();
    // Trees built for the same mesh and parameters are traced again, not rebuilt.
    std::shared_ptr<const BvhPair> built = result_ && result_->key.same_trees(key) ? result_->pair : nullptr;
    job_.submit([key, scene = std::move(scene), progress = progress_, built = std::move(built)]() {
        Result result;
        result.key = key;
        result.scene = scene;
        result.pair = built;
        if (!result.pair) {
            // Two BVHs beside the scene's own structure: refused, not an out-of-memory kill.
            AccelConfig bvh;
            bvh.type = AccelType::Bvh;
            bvh.bvh = key.config;
            const uint64_t need = 2 * fixed_build_bytes(bvh, scene->mesh->triangle_count());
            const uint64_t budget = scene->accel_config.memory_budget ? scene->accel_config.memory_budget
                                                                      : default_memory_budget();
            if (need > budget) {
                result.error = "two BVHs of this mesh need " + format_bytes(need) + ", over the memory budget (" +
                               format_bytes(budget) + ")";
                return result;
            }
            auto pair = build_bvh_pair(*scene->mesh, key.config, key.builders, progress.get());
            if (!pair) {
                result.error = pair.error();
                return result;
            }
            result.pair = std::make_shared<const BvhPair>(std::move(*pair));
        }
        TwoBvhsOptions options;
        options.traversal = key.traversal;
        options.progress = progress.get();
        auto measured =
            measure_two_bvhs(*result.pair, *scene->mesh, Camera(key.camera, key.width, key.height), options);
        if (!measured) {
            result.error = measured.error();
            return result;
        }
        for (size_t i = 0; i < 2; ++i) result.drawn[i] = boxes_to_draw(measured->trees[i], result.drawn_depth[i]);
        crop_to_scene(result, Camera(key.camera, key.width, key.height), scene->bounds);
        result.trees = std::move(*measured);
        return result;
    });
}

void TwoBvhsPanel::take_finished() {
    auto done = job_.take();
    if (!done) return;
    if (done->trees) result_ = std::move(*done);
    else if (done->error != WorkProgress::cancelled_error().message) error_ = done->error;
}

void TwoBvhsPanel::update(const AppState& state, const std::shared_ptr<const LoadedScene>& scene, int view_width,
                          int view_height, bool shown, bool wait) {
    if (!shown || !scene || !state.camera || view_width <= 0 || view_height <= 0) {
        if (job_.busy() && progress_) progress_->cancel();
        requested_.reset();  // the next showing measures again
        take_finished();
        if (result_) result_->pair.reset();  // two trees of a big mesh are not kept for a hidden panel
        return;
    }
    BvhConfig config = state.accel.bvh;
    config.builder = BvhBuilder::SahBinned;  // not used: the two builders are the panel's
    config.width = 2;                        // the panel compares two binary trees, whatever the scene's width
    const Key key{scene->mesh.get(), config, state.accel.bvh_traversal, state.two_bvhs.builders,
                  *state.camera, view_width, view_height};
    take_finished();  // a finished build's trees serve this view
    const bool new_mesh = requested_mesh_.lock() != scene->mesh;
    if (!requested_ || !(*requested_ == key) || new_mesh) {
        // A moved camera while the trees are being built: let the build finish (this view
        // is measured next, through those trees) rather than start it again each frame.
        const bool building_these_trees = job_.busy() && requested_ && requested_->same_trees(key) && !new_mesh &&
                                          !(result_ && result_->pair && result_->key.same_trees(key));
        if (!building_these_trees) start(key, scene);
    }
    if (wait) job_.wait();
    take_finished();
}

void TwoBvhsPanel::draw_tree(const Result& result, size_t which, float width, float height) const {
    const BvhTreeSummary& tree = result.trees->trees[which];
    const ImVec2 p0 = ImGui::GetCursorScreenPos(), p1(p0.x + width, p0.y + height);
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->AddRectFilled(p0, p1, kCanvasBg);
    draw->PushClipRect(p0, p1, true);
    const Camera camera(result.key.camera, result.key.width, result.key.height);
    const float scale = width / float(result.crop_x1 - result.crop_x0);
    auto to_screen = [&](Vec3 p, ImVec2& out) {
        const Camera::ImagePoint q = camera.project(to_double(p));
        out = ImVec2(p0.x + float(q.x - result.crop_x0) * scale, p0.y + float(q.y - result.crop_y0) * scale);
        return q.depth > 0;
    };
    const Mesh& mesh = *result.scene->mesh;
    if (mesh.triangle_count() <= kMaxTrianglesDrawn)
        for (uint32_t t = 0; t < mesh.triangle_count(); ++t) {
            ImVec2 a, b, c;
            if (to_screen(mesh.vertex(t, 0), a) && to_screen(mesh.vertex(t, 1), b) && to_screen(mesh.vertex(t, 2), c))
                draw->AddTriangleFilled(a, b, c, kLeafColours[tree.leaf_of_triangle[t] % std::size(kLeafColours)]);
        }
    const float line = std::max(1.5f, 0.1f * ImGui::GetFontSize());
    const uint32_t deepest = result.drawn_depth[which];
    for (uint32_t i : result.drawn[which]) {
        const auto& box = tree.boxes[i];
        ImVec2 corner[8];
        bool visible = true;
        for (int k = 0; k < 8; ++k) {
            const Vec3 p{k & 1 ? box.bounds.hi.x : box.bounds.lo.x, k & 2 ? box.bounds.hi.y : box.bounds.lo.y,
                         k & 4 ? box.bounds.hi.z : box.bounds.lo.z};
            visible &= to_screen(p, corner[k]);
        }
        if (!visible) continue;  // a box reaching behind the eye: no outline to draw
        const ImU32 colour = depth_colour(box.depth, deepest);
        for (int k = 0; k < 8; ++k)
            for (int bit : {1, 2, 4})
                if (!(k & bit)) draw->AddLine(corner[k], corner[k | bit], colour, line);
    }
    draw->PopClipRect();
    draw->AddRect(p0, p1, kCanvasFrame);
}

void TwoBvhsPanel::draw(AppState& state, float width, bool lecture) {
    ImGui::PushTextWrapPos(0.0f);
    const TwoBvhs* m = measured();
    if (m && result_->scene)
        ImGui::Text("Two BVHs over the same %zu triangles: which is better?", result_->scene->mesh->triangle_count());
    else
        ImGui::TextUnformatted("Two BVHs over the same triangles: which is better?");
    if (job_.busy()) {
        ImGui::TextUnformatted("Building both trees ...");
        progress_with_cancel(progress_.get(), width);
    }
    if (!error_.empty() && !job_.busy()) error_line("Could not build", error_);
    // Which tree is which: the builder combos, or in lecture mode their names.
    const float half = 0.5f * (width - ImGui::GetStyle().ItemSpacing.x);
    const float second_x = ImGui::GetCursorPosX() + half + ImGui::GetStyle().ItemSpacing.x;
    if (!lecture) {
        ImGui::SetNextItemWidth(half);
        builder_combo("##left builder", state.two_bvhs.builders[0]);
        ImGui::SameLine(second_x);
        ImGui::SetNextItemWidth(half);
        builder_combo("##right builder", state.two_bvhs.builders[1]);
    } else if (m) {
        ImGui::TextUnformatted(std::string(to_string(m->trees[0].builder)).c_str());
        ImGui::SameLine(second_x);
        ImGui::TextUnformatted(std::string(to_string(m->trees[1].builder)).c_str());
    }
    if (!m) {
        ImGui::PopTextWrapPos();
        return;
    }
    // The two pictures side by side, the view's shape, leaving room for the table below.
    const float gap = ImGui::GetStyle().ItemSpacing.x;
    const float pic_w = 0.5f * (width - gap);
    const float aspect = float((result_->crop_y1 - result_->crop_y0) / (result_->crop_x1 - result_->crop_x0));
    const float room = ImGui::GetContentRegionAvail().y - (lecture ? 9.0f : 13.0f) * ImGui::GetTextLineHeightWithSpacing();
    const float pic_h = std::max(3.0f * ImGui::GetFontSize(), std::min(pic_w * aspect, room));
    const float pic_w_shown = std::min(pic_w, pic_h / aspect);  // a short panel: narrower pictures, same shape
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    for (size_t i = 0; i < 2; ++i) {
        ImGui::SetCursorScreenPos(ImVec2(origin.x + float(i) * (pic_w + gap), origin.y));
        draw_tree(*result_, i, pic_w_shown, pic_w_shown * aspect);
    }
    ImGui::SetCursorScreenPos(ImVec2(origin.x, origin.y + pic_w_shown * aspect));
    ImGui::Dummy(ImVec2(width, 0.2f * ImGui::GetFontSize()));
    std::string levels;
    for (size_t i = 0; i < 2; ++i) {
        const BvhTreeSummary& tree = m->trees[i];
        if (result_->drawn_depth[i] < tree.stats.max_depth)
            levels += "; " + std::string(to_string(tree.builder)) + ": levels 0-" +
                      std::to_string(result_->drawn_depth[i]) + " of " + std::to_string(tree.stats.max_depth);
    }
    const bool filled = result_->scene->mesh->triangle_count() <= kMaxTrianglesDrawn;
    ImGui::TextDisabled("Boxes by depth (root dark, deepest bright), %s%s.",
                        filled ? "triangles by leaf" : "triangles not drawn (too many to fill)", levels.c_str());
    draw_table(*m, lecture);
    ImGui::PopTextWrapPos();
}

void TwoBvhsPanel::draw_table(const TwoBvhs& m, bool lecture) const {
    const BvhTreeSummary& a = m.trees[0];
    const BvhTreeSummary& b = m.trees[1];
    constexpr ImGuiTableFlags kFlags =
        ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp | ImGuiTableFlags_BordersInnerV;
    ImGui::PushTextWrapPos(-1.0f);
    if (ImGui::BeginTable("two_bvhs", 3, kFlags)) {
        ImGui::TableSetupColumn("");
        ImGui::TableSetupColumn(std::string(to_string(a.builder)).c_str());
        ImGui::TableSetupColumn(std::string(to_string(b.builder)).c_str());
        ImGui::TableHeadersRow();
        // A row of figures; `lower_is_better`: the smaller one is lit.
        auto row = [](const char* what, double x, double y, const char* format, bool lower_is_better) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(what);
            for (double v : {x, y}) {
                ImGui::TableNextColumn();
                const bool lit = lower_is_better && x != y && v == std::min(x, y);
                if (lit) ImGui::PushStyleColor(ImGuiCol_Text, kBetter);
                ImGui::TextUnformatted(text_of(format, v).c_str());
                if (lit) ImGui::PopStyleColor();
            }
        };
        row("SAH cost", a.stats.sah_cost, b.stats.sah_cost, "%.2f", true);
        row("nodes visited / ray", a.nodes_per_ray, b.nodes_per_ray, "%.2f", true);
        row("box tests / ray", a.box_tests_per_ray, b.box_tests_per_ray, "%.2f", true);
        row("triangle tests / ray", a.triangle_tests_per_ray, b.triangle_tests_per_ray, "%.2f", true);
        row("nodes", a.stats.nodes, b.stats.nodes, "%.0f", false);
        row("leaves", a.stats.leaves, b.stats.leaves, "%.0f", false);
        row("depth", a.stats.max_depth, b.stats.max_depth, "%.0f", false);
        ImGui::EndTable();
    }
    ImGui::PopTextWrapPos();
    // The answer, in a sentence.
    const bool a_cheaper = a.stats.sah_cost < b.stats.sah_cost;
    const BvhTreeSummary& cheaper = a_cheaper ? a : b;
    const BvhTreeSummary& dearer = a_cheaper ? b : a;
    const bool fewer_nodes_too = cheaper.nodes_per_ray <= dearer.nodes_per_ray;
    if (a.stats.sah_cost == b.stats.sah_cost)
        ImGui::TextWrapped("Both trees have the same SAH cost.");
    else if (fewer_nodes_too)
        ImGui::TextWrapped("The %s tree is better: SAH cost %.2f against %.2f, and the rays of this view that "
                           "reach the trees visit %.2f nodes each against %.2f.",
                           std::string(to_string(cheaper.builder)).c_str(), cheaper.stats.sah_cost,
                           dearer.stats.sah_cost, cheaper.nodes_per_ray, dearer.nodes_per_ray);
    else
        ImGui::TextWrapped("The %s tree has the lower SAH cost (%.2f against %.2f), yet the rays of this view "
                           "that reach the trees visit more of its nodes (%.2f against %.2f): the cost assumes rays spread evenly over the "
                           "root's box, and these are not.",
                           std::string(to_string(cheaper.builder)).c_str(), cheaper.stats.sah_cost,
                           dearer.stats.sah_cost, cheaper.nodes_per_ray, dearer.nodes_per_ray);
    if (!lecture) {
        ImGui::TextDisabled("SAH cost: the expected cost of a ray that meets the root's box, C_trav per node it "
                            "enters and C_isect per triangle it tests, each node weighted by S_node / S_root. Per "
                            "ray: over the %llu of %llu sampled pixels of this view whose rays meet the root's box "
                            "(%llu hit a triangle).",
                            (unsigned long long)m.rays_meeting_root, (unsigned long long)m.rays,
                            (unsigned long long)m.rays_that_hit);
        if (m.disagreements > 0) {
            ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(255, 120, 100, 255));
            ImGui::Text("%llu rays found different closest hits in the two trees.", (unsigned long long)m.disagreements);
            ImGui::PopStyleColor();
        }
    }
}

}  // namespace accelviz
