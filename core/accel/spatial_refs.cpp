#include "core/accel/spatial_refs.h"

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

}  // namespace accelviz
