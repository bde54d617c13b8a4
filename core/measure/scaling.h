#pragma once
/// The lecture's last slide, measured: rasterization must touch every triangle, ray
/// casting through a hierarchy need not. One mesh is repeated 1, 2, 4, ... times on
/// a grid (repeat_on_grid, as builtin:instances does), and for each scene, seen
/// whole by its default camera, this measures the frame time of rasterizing it (the
/// CPU z-buffer of core/render/rasterizer.h on one thread and, when the caller has
/// an OpenGL context, OpenGL's) and of ray casting it through each structure asked
/// for (built first; the build time is kept too). On scaling_chart's log-log axes a
/// cost proportional to the triangle count is a line of slope 1; the BVH's ray cast
/// grows roughly with the logarithm of the count, so its line is nearly flat.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/accel/factory.h"
#include "core/geometry/mesh.h"
#include "core/render/camera.h"
#include "core/render/chart.h"
#include "core/util/expected.h"
#include "core/util/work_progress.h"

namespace accelviz {

struct ScalingOptions {
    std::vector<AccelConfig> structures = {bvh_config_default()};  ///< each built with these parameters
    uint64_t max_triangles = 10'500'000;  ///< the biggest scene's count is at most this (one copy at least)
    int width = 640, height = 360;        ///< every frame's size
    int threads = 0;                      ///< the ray casts' threads (0: all cores; builds use oneTBB's limit)
    int repeat = 3;                       ///< frames per figure; their median (the upper middle one) is kept
    /// One rasterized frame of `mesh` by OpenGL, in milliseconds to glFinish, when the
    /// caller has a context (OSMesa for `render`, the window's own); empty: the CPU
    /// z-buffer only. Called `repeat` times per scene after one frame not timed.
    std::function<Expected<double>(const Mesh& mesh, const Camera& camera)> gl_raster_ms;
    /// Hears each step ("4 copies, 1.1M triangles: building bvh") before it starts.
    std::function<void(const std::string& step)> on_step;
    /// The builds report here and anything may cancel (measure_scaling then returns
    /// WorkProgress::cancelled_error()).
    WorkProgress* progress = nullptr;
};

/// One scene's figures.
struct ScalingPoint {
    uint64_t copies = 1, triangles = 0;
    double cpu_raster_ms = 0;             ///< the CPU z-buffer, one thread
    std::optional<double> gl_raster_ms;   ///< OpenGL, when measured
    std::vector<double> build_ms;         ///< per structure, in ScalingOptions::structures' order
    std::vector<double> cast_ms;          ///< per structure: one ray per pixel, closest hit, shaded
};

struct ScalingResult {
    std::string mesh_name;
    uint64_t mesh_triangles = 0;
    std::vector<AccelConfig> structures;
    std::vector<ScalingPoint> points;  ///< in increasing size
    int width = 0, height = 0, threads = 0;
    std::string gl_renderer;  ///< who rasterized with OpenGL (its GL_RENDERER), for the table
    /// Why the scenes stop before max_triangles ("" when they do not): a structure
    /// that would not fit the memory budget, for example.
    std::string stopped_early;
};

/// At most this many scenes (2^19 copies of a mesh).
inline constexpr size_t kScalingMaxScenes = 20;

/// The copies of each scene: 1, 2, 4, ... while copies x triangles <= max_triangles
/// (always 1 first), at most kScalingMaxScenes of them.
std::vector<uint64_t> scaling_copies(uint64_t triangles, uint64_t max_triangles);
/// The grid of `copies` (a power of two): nx = nz, or nx = 2·nz.
std::pair<uint64_t, uint64_t> scaling_grid(uint64_t copies);

/// Measures every scene of scaling_copies(one's triangles, max_triangles), one
/// structure at a time (built, cast, freed). A scene that cannot be made or whose
/// structure cannot be built (the memory budget) ends the series with stopped_early
/// set; an empty mesh, naive (every triangle for every ray) or bad parameters is an
/// error.
Expected<ScalingResult> measure_scaling(const Mesh& one, const ScalingOptions& options);

/// The log-log chart: frame milliseconds against triangles, one line per raster and
/// per structure's ray cast.
LineChart scaling_chart(const ScalingResult& result);

/// The figures as a Markdown table (one row per scene).
std::string scaling_table(const ScalingResult& result);

}  // namespace accelviz
