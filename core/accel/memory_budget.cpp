#include "core/accel/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/accel/bvh.h"
#include "core/accel/bvh_splitter.h"
#include "core/accel/spatial_refs.h"

namespace accelviz {

namespace {

/// One triangle of the copy every structure keeps (per triangle or per reference), and
/// its corners with the watertight test.
uint64_t triangle_copy_bytes(const AccelConfig& config) {
    return sizeof(Triangle) + (config.triangle_test == TriangleTestKind::Watertight ? sizeof(TriangleCorners) : 0);
}

/// The most cells the grid's resolution rule can give: each axis' count is rounded
/// from its exact share (at most 1.5 times it), then the caps.
uint64_t grid_cells_bound(const GridConfig& grid, uint64_t triangles) {
    const double rule = std::ceil(double(grid.density) * double(triangles) * 3.375) + 1.0;
    const double per_axis = std::pow(double(grid.max_cells_per_axis), 3.0);
    return uint64_t(std::min({rule, per_axis, double(grid.max_cells)}));
}

/// What to change when a structure's fixed part does not fit.
const char* what_to_change(AccelType type) {
    switch (type) {
        case AccelType::Grid: return "lower --grid-density, ";
        default: return "";
    }
}

}  // namespace

uint64_t default_memory_budget() {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page <= 0) return uint64_t(4) << 30;
    return uint64_t(pages) * uint64_t(page) / 2;
}

std::string format_bytes(uint64_t bytes) {
    char text[32];
    if (bytes >= (uint64_t(1) << 30)) std::snprintf(text, sizeof text, "%.1f GB", double(bytes) / double(1 << 30));
    else if (bytes >= (uint64_t(1) << 20)) std::snprintf(text, sizeof text, "%.0f MB", double(bytes) / double(1 << 20));
    else if (bytes >= 1024) std::snprintf(text, sizeof text, "%.0f KB", double(bytes) / 1024.0);
    else std::snprintf(text, sizeof text, "%llu bytes", static_cast<unsigned long long>(bytes));
    return text;
}

std::optional<uint64_t> parse_memory_size(std::string_view text) {
    if (text.empty()) return std::nullopt;
    double unit = 1.0;
    switch (text.back()) {
        case 'K': case 'k': unit = 1024.0; break;
        case 'M': case 'm': unit = 1024.0 * 1024.0; break;
        case 'G': case 'g': unit = 1024.0 * 1024.0 * 1024.0; break;
        case 'T': case 't': unit = 1024.0 * 1024.0 * 1024.0 * 1024.0; break;
        default: break;
    }
    if (unit > 1.0) text.remove_suffix(1);
    if (text.empty() || text.size() > 32) return std::nullopt;
    const std::string number(text);
    char* end = nullptr;
    const double value = std::strtod(number.c_str(), &end);
    if (end != number.c_str() + number.size() || !(value > 0.0) || !std::isfinite(value)) return std::nullopt;
    const double bytes = value * unit;
    if (bytes < 1.0 || bytes > 1e18) return std::nullopt;
    return uint64_t(bytes);
}

uint64_t fixed_build_bytes(const AccelConfig& config, uint64_t triangles) {
    const uint64_t copy = triangle_copy_bytes(config) * triangles;
    switch (config.type) {
        case AccelType::Naive: return copy;
        case AccelType::Bvh:
            // The build's references, then at most 2N - 1 nodes (leaves of one
            // triangle), the leaf order and the triangle copy.
            return triangles * (sizeof(bvh_detail::PrimRef) + 2 * sizeof(BvhNode) + sizeof(uint32_t)) + copy;
        case AccelType::Grid:
            // The cells' list starts and the first pass's per-triangle offsets; the
            // grid's triangles are by id, not per reference.
            return (grid_cells_bound(config.grid, triangles) + 1) * sizeof(uint32_t) + triangles * sizeof(uint32_t) +
                   copy;
        case AccelType::Kd:
            // The corners the splits read; with the SAH, the sorted bounds at their
            // largest, when the root splits (kd_sorted_bounds.h): the root's six lists
            // and its children's (8 bytes a bound, about 48 + 53 bytes a triangle) and
            // the map between them, 8; the root's sorts take up to 16 bytes a triangle
            // a list sorted at once, six at most: 144 in all.
            return triangles * (sizeof(CornerTriples::value_type) + (config.kd.builder == KdBuilder::Sah ? 144 : 0));
        case AccelType::Octree:
            // The same in Morton order, each triangle's padded box, that order (the tree
            // keeps it: copy_order), and the triangle copy, one per triangle
            // (PartitionTree's kOneCopyPerTriangle).
            return triangles * (sizeof(CornerTriples::value_type) + sizeof(Aabb) + sizeof(uint32_t)) + copy;
        case AccelType::Bsp: return 0;  // all per reference
    }
    return copy;
}

uint64_t bytes_per_reference(const AccelConfig& config) {
    switch (config.type) {
        case AccelType::Naive:
        case AccelType::Bvh: return 0;
        case AccelType::Grid: return 2 * sizeof(uint32_t);  // the first pass's cell id, the list entry
        case AccelType::Kd:
        case AccelType::Octree:
            // A reference under construction (the KD tree's SpatialRef, the octree's
            // Morton place), its leaf's id in the subtree and in the spliced tree, then
            // the KD tree's triangle copy or the octree's copy index (its one copy per
            // triangle is counted above), and an allowance of 24 bytes for nodes and the
            // splits' scratch (measured peaks: KD tree 69-74 bytes per reference in all;
            // octree, 871k, 5.7M references: 291 MB for the process, 104 MB of it
            // without a structure, against this estimate's 315 MB; docs/performance.md).
            return config.type == AccelType::Kd
                       ? sizeof(SpatialRef) + 2 * sizeof(uint32_t) + triangle_copy_bytes(config) + 24
                       : sizeof(uint32_t) + 2 * sizeof(uint32_t) + sizeof(uint32_t) + 24;
        case AccelType::Bsp:
            // A piece under construction (a polygon of up to 9 corners, 116 bytes), its
            // leaf id, its triangle copy and the same allowance for nodes.
            return 116 + sizeof(uint32_t) + triangle_copy_bytes(config) + 24;
    }
    return 0;
}

Expected<AccelConfig> fit_memory_budget(const AccelConfig& config, uint64_t triangles, uint64_t budget,
                                        std::string* note) {
    if (budget == 0) budget = default_memory_budget();
    const std::string name(to_string(config.type));
    const uint64_t fixed = fixed_build_bytes(config, triangles);
    const uint64_t per_ref = bytes_per_reference(config);
    // The trees need at least one reference per triangle (the root's).
    const uint64_t least = fixed + (config.type == AccelType::Grid ? 0 : per_ref * triangles);
    if (least > budget)
        return Error{name + " over " + std::to_string(triangles) + " triangles needs about " + format_bytes(least) +
                     ", more than the memory budget of " + format_bytes(budget) + ": " + what_to_change(config.type) +
                     "use a smaller scene or raise --memory-budget"};
    AccelConfig out = config;
    if (per_ref == 0 || triangles == 0) return out;
    const uint64_t references = (budget - fixed) / per_ref;
    auto say = [&](const std::string& text) {
        if (note) *note = "memory budget " + format_bytes(budget) + ": " + text;
    };
    if (config.type == AccelType::Grid) {
        if (references < config.grid.max_references) {
            out.grid.max_references = std::max<uint64_t>(references, 1);
            say("at most " + std::to_string(out.grid.max_references) + " cell entries (--memory-budget)");
        }
        return out;
    }
    double& duplication = config.type == AccelType::Kd       ? out.kd.max_duplication
                          : config.type == AccelType::Octree ? out.octree.max_duplication
                                                             : out.bsp.max_duplication;
    const double fits = double(references) / double(triangles);
    if (fits < duplication) {
        duplication = std::max(1.0, std::floor(fits * 100.0) / 100.0);
        char text[96];
        std::snprintf(text, sizeof text, "reference budget lowered to %.2f x triangles (--memory-budget)", duplication);
        say(text);
    }
    return out;
}

}  // namespace accelviz
