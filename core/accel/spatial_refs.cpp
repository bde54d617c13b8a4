#include "core/accel/spatial_refs.h"

#include <sstream>

#include "core/geometry/triangle_box.h"

namespace accelviz {

std::string_view to_string(ClipMode mode) { return mode == ClipMode::Box ? "box" : "exact"; }

std::optional<ClipMode> parse_clip_mode(std::string_view name) {
    if (name == "box") return ClipMode::Box;
    if (name == "exact") return ClipMode::Exact;
    return std::nullopt;
}

const std::vector<std::string>& clip_mode_names() {
    static const std::vector<std::string> names = {"box", "exact"};
    return names;
}

std::vector<SpatialRef> root_references(const Mesh& mesh, float pad) {
    std::vector<SpatialRef> refs(mesh.triangle_count());
    for (uint32_t t = 0; t < refs.size(); ++t) refs[t] = {t, padded(mesh.triangle_bounds(t), pad)};
    return refs;
}

std::optional<SpatialRef> clip_reference(const SpatialRef& ref, const Mesh& mesh, const Aabb& child, float pad,
                                         ClipMode mode) {
    // The reference's box is its part grown by pad, so it fits in child grown by 2·pad
    // exactly when the part fits in child grown by pad: nothing to clip.
    const Aabb limit = padded(child, 2 * pad);
    if (limit.contains(ref.box)) return ref;
    if (mode == ClipMode::Box) {
        const Aabb box = intersection(ref.box, limit);
        if (box.empty()) return std::nullopt;
        return SpatialRef{ref.tri, box};
    }
    const Aabb part = clip_triangle_to_box(mesh.vertex(ref.tri, 0), mesh.vertex(ref.tri, 1), mesh.vertex(ref.tri, 2),
                                           padded(child, pad));
    if (part.empty()) return std::nullopt;
    // Never grow beyond what the parent had (clipping is monotone; this absorbs rounding).
    const Aabb box = intersection(padded(part, pad), ref.box);
    if (box.empty()) return std::nullopt;
    return SpatialRef{ref.tri, box};
}

void add_split_notes(const SplitStops& stops, std::vector<std::string>& notes) {
    if (stops.leaves_at_depth_limit > 0) {
        std::ostringstream s;
        s << stops.leaves_at_depth_limit << " leaves stopped at the depth limit " << stops.depth_limit
          << " with more than leaf_size = " << stops.leaf_size << " references";
        notes.push_back(s.str());
    }
    if (stops.not_split > 0) {
        std::ostringstream s;
        s << stops.not_split << " " << stops.parts << " made leaves: " << stops.not_split_why;
        notes.push_back(s.str());
    }
    if (stops.budget_hit) {
        std::ostringstream s;
        s << "reference budget reached (" << stops.max_duplication << " x triangles): later " << stops.parts
          << " were made leaves instead of being split";
        notes.push_back(s.str());
    }
}

nlohmann::json partition_stats_json(const PartitionStats& s) {
    return {{"triangles", s.triangles},
            {"nodes", s.nodes},
            {"leaves", s.leaves},
            {"empty_leaves", s.empty_leaves},
            {"max_depth", s.max_depth},
            {"references", s.references},
            {"duplication", s.duplication},
            {"max_leaf_size", s.max_leaf_size},
            {"padding", s.padding},
            {"memory_bytes", s.memory_bytes},
            {"build_ms", s.build_ms},
            {"notes", s.notes}};
}

}  // namespace accelviz
