#pragma once
/// Everything the window shows, as plain data: which scene, which structure and
/// its parameters, the camera, and the view settings. It serializes to JSON (a
/// preset is a saved AppState), and the window and headless renders draw from
/// it alone, so the same AppState gives the same picture in both.
/// Runtime things (the loaded mesh, GPU buffers, error messages) live in Session.

#include <array>
#include <optional>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/accel/factory.h"
#include "core/render/camera.h"
#include "core/render/frame.h"
#include "core/render/lighting.h"
#include "core/util/enum_names.h"
#include "core/util/expected.h"

namespace accelviz {

/// The 3D view alone, or raster vs ray cast side by side (S).
enum class ViewMode { View3D, Split };
inline constexpr EnumNames<ViewMode, 2> kViewModeNames{{{{ViewMode::View3D, "3d"}, {ViewMode::Split, "split"}}}};

/// What the right half of the split view shows: the ray caster's picture of the
/// camera, shaded; its work per pixel through the current structure (heat maps);
/// its depth as grey, on one scale with the rasterizer's; or where the core
/// rasterizer's and the ray caster's depths disagree.
enum class RightView { RayCast, HeatNodes, HeatTris, Depth, DepthDiff, HeatStack };
inline constexpr EnumNames<RightView, 6> kRightViewNames{{{{RightView::RayCast, "raycast"},
                                                           {RightView::HeatNodes, "heat-nodes"},
                                                           {RightView::HeatTris, "heat-tris"},
                                                           {RightView::Depth, "depth"},
                                                           {RightView::DepthDiff, "depth-diff"},
                                                           {RightView::HeatStack, "heat-stack"}}}};

/// Who casts the split view's right half: the CPU ray caster (every structure), or
/// the GPU's compute shader (the binary BVH, OpenGL 4.3: app/gl/gpu_ray_caster.h).
/// heat-stack (each invocation's deepest stack) is the GPU's alone.
enum class RayCastBy { Cpu, Gpu };
inline constexpr EnumNames<RayCastBy, 2> kRayCastByNames{{{{RayCastBy::Cpu, "cpu"}, {RayCastBy::Gpu, "gpu"}}}};
constexpr std::string_view to_string(RayCastBy v) { return kRayCastByNames.name(v); }

/// What the left half shows: the live OpenGL view (its own z-buffer), the core
/// CPU rasterizer's image of the same camera, its depth as grey (one scale with
/// the ray cast's), or OpenGL's depth buffer read back.
enum class LeftView { OpenGl, Raster, RasterDepth, OpenGlDepth };
inline constexpr EnumNames<LeftView, 4> kLeftViewNames{{{{LeftView::OpenGl, "opengl"},
                                                         {LeftView::Raster, "raster"},
                                                         {LeftView::RasterDepth, "raster-depth"},
                                                         {LeftView::OpenGlDepth, "opengl-depth"}}}};

/// How the 3D view draws the mesh: rasterized by OpenGL (every triangle, z-buffer),
/// ray cast by the CPU through the current structure (a ray per pixel; its depth
/// written to the z-buffer so the overlay is hidden behind the surface as before),
/// or whichever the last frames measured faster (the lecture's last slide:
/// rasterization touches every triangle, a ray through a hierarchy need not).
enum class DrawWith { Raster, RayCast, Auto };
inline constexpr EnumNames<DrawWith, 3> kDrawWithNames{
    {{{DrawWith::Raster, "raster"}, {DrawWith::RayCast, "raycast"}, {DrawWith::Auto, "auto"}}}};

constexpr std::string_view to_string(ViewMode v) { return kViewModeNames.name(v); }
constexpr std::string_view to_string(DrawWith v) { return kDrawWithNames.name(v); }
constexpr std::string_view to_string(RightView v) { return kRightViewNames.name(v); }
constexpr std::string_view to_string(LeftView v) { return kLeftViewNames.name(v); }

inline std::ostream& operator<<(std::ostream& out, ViewMode v) { return out << to_string(v); }
inline std::ostream& operator<<(std::ostream& out, DrawWith v) { return out << to_string(v); }
inline std::ostream& operator<<(std::ostream& out, RightView v) { return out << to_string(v); }
inline std::ostream& operator<<(std::ostream& out, LeftView v) { return out << to_string(v); }

/// Whose work a heat map shows: the camera's rays, or the point light's secondary
/// rays (shadow, reflection; LightSettings).
enum class HeatRays { Primary, Shadow, Reflection };
inline constexpr EnumNames<HeatRays, 3> kHeatRaysNames{
    {{{HeatRays::Primary, "primary"}, {HeatRays::Shadow, "shadow"}, {HeatRays::Reflection, "reflection"}}}};
constexpr std::string_view to_string(HeatRays v) { return kHeatRaysNames.name(v); }

/// A heat map (work per pixel) on the right.
constexpr bool is_heat(RightView v) { return v == RightView::HeatNodes || v == RightView::HeatTris; }

/// How the window looks; the lecture-hall settings.
struct ViewSettings {
    float ui_scale = 1.0f;          ///< panels and text; 1 = 16 px text, 1.5 to 2.5 for a projector
    bool light_theme = false;       ///< dark text on light panels (washed-out projectors)
    Rgb background = kBackground;   ///< 3D view background (the CPU views' background by default)
    bool show_ui = true;            ///< panels and status bar (Tab hides them)
    bool show_help = false;         ///< the keyboard shortcuts window (F1)
    bool show_bounds = true;        ///< the scene's bounding box as a wireframe
    float line_width = 1.0f;        ///< pixels, 1 to 6: box edges and segments (wider for projectors)
    ViewMode mode = ViewMode::View3D;
    /// The 3D view's mesh (not the split view's halves). Auto: a small mesh is
    /// rasterized, a big one (estimated over 30 ms to rasterize) ray cast from its
    /// first frame, so a 10M-triangle scene does not start at seconds a frame.
    DrawWith draw_with = DrawWith::Auto;
    RightView right_view = RightView::RayCast;  ///< in the split view
    LeftView left_view = LeftView::OpenGl;      ///< in the split view
    /// Heat maps keep the largest count seen since the scene was loaded as the top
    /// of their scale, so that switching structures compares like with like.
    bool heat_same_scale = false;
    HeatRays heat_rays = HeatRays::Primary;  ///< the rays whose work the heat maps show
    /// The split view's fill order (the lecture's two loops, stopped part-way): the CPU
    /// rasterizer after the first `fill` of its triangles on the left, the ray caster
    /// after the first `fill` of its pixels on the right (0 to 1).
    bool fill_order = false;
    float fill = 1.0f;
    RayCastBy ray_cast_by = RayCastBy::Cpu;  ///< the split view's right half
    /// The inside/outside slice (core/query/inside_slice.h): a plane across the scene
    /// perpendicular to axis `slice_axis` (0 x, 1 y, 2 z) at `slice_at` (0..1 of the
    /// mesh's box), its points coloured by the ray-parity vote, drawn in the 3D view.
    bool slice = false;
    int slice_axis = 2;
    float slice_at = 0.5f;

    bool operator==(const ViewSettings&) const = default;
};

/// What of the current structure the 3D view draws over the mesh.
struct OverlaySettings {
    bool show_structure = true;  ///< BVH/octree boxes, grid cells, KD planes
    /// Levels shown (root = 0), inclusive; BVH, KD tree and octree. Level k
    /// alone: level_min = level_max = k.
    int level_min = 0;
    int level_max = 64;
    bool leaves_only = false;    ///< BVH/octree: only the leaves' boxes; KD: non-empty leaves' boxes
    float mesh_opacity = 1.0f;   ///< < 1: see the structure through the mesh (x-ray)
    /// Box budget: deeper levels are left out once the levels shown would draw
    /// more boxes than this (0: no limit). A software renderer (llvmpipe) draws
    /// about a million box edges per 100 ms; a GPU, far more.
    size_t max_boxes = 200000;
    bool operator==(const OverlaySettings&) const = default;
};

/// The construction stepper (BVH): which of the builder's decisions the window
/// shows, and the SAH chart's own parameters (the live sliders; unset = the
/// parameters the tree was built with). Rule shared with the traversal stepper:
/// the active stepper owns the arrow keys (Left/Right/Home/End), and turning one
/// on turns the other off.
struct BuildStepSettings {
    bool active = false;  ///< the Construction panel is open: the 3D view shows the node being split
    /// The decision shown: 0 = the root's, in the BVH builder's order (depth first); or,
    /// stepping a KD tree or a file's tree node by node, the node number.
    int step = 0;
    std::optional<int> bins;           ///< chart only: B for binned SAH
    std::optional<float> cost_trav;    ///< charts and the panel's costs only (the tree stays): C_trav
    std::optional<float> cost_isect;   ///< charts and the panel's costs only: C_isect
    bool operator==(const BuildStepSettings&) const = default;
};

/// The font size in pixels for a UI scale (16 px at scale 1, 8 to 64 px).
int font_pixels(float ui_scale);

/// The traversal stepper: one ray, recorded once through the current
/// structure, stepped event by event. The ray and the step are state (presets
/// and `render --view step` reproduce them); playing is not (no animation in a
/// saved or headless frame).
struct StepperSettings {
    bool open = false;             ///< the Stepper panel is shown and its ray drawn in the 3D view
    std::optional<Ray> ray;        ///< the ray stepped (none: click a pixel or type one)
    size_t step = 0;               ///< events applied (0: before the first; past the end: the final state)
    std::optional<std::array<int, 2>> pixel;  ///< where the ray was picked (for the panel's caption), if by a pixel
    /// The ray is a shadow ray, stepped by the any-hit query (it stops at the first
    /// triangle in [t_min, t_max]); false: the closest-hit query (camera, reflection).
    bool any_hit = false;
    bool operator==(const StepperSettings&) const = default;
};

/// The nearest-point stepper: the point on the mesh nearest to a query point, found
/// through the structure on screen (naive, the binary BVH or the KD tree) and stepped
/// event by event in a right panel; the query point is dragged in the 3D view.
struct NearestSettings {
    bool open = false;
    std::optional<Vec3d> point;  ///< empty: default_query_point(the scene's bounds)
    size_t step = 0;             ///< events applied (past the end: the final state)
    bool operator==(const NearestSettings&) const = default;
};

/// The comparison panel: every structure measured on the current scene and
/// camera (build, memory, time and work per ray) and the amortization chart.
/// Opening it closes the steppers' panels (one right panel at a time).
struct ComparisonSettings {
    bool open = false;
    bool operator==(const ComparisonSettings&) const = default;
};

/// The lecture's "two BVHs over the same triangles: which is better?": a panel
/// with the current scene's BVH made by two builders side by side (every other
/// build parameter from the structure's), their boxes, SAH costs and work per ray.
struct TwoBvhsSettings {
    bool open = false;
    std::array<BvhBuilder, 2> builders{BvhBuilder::Median, BvhBuilder::SahBinned};  ///< left, right
    bool operator==(const TwoBvhsSettings&) const = default;
};

/// The structures the scaling chart offers (naive would test every triangle for every ray).
inline constexpr std::array<AccelType, 4> kScalingStructures{AccelType::Bvh, AccelType::Kd, AccelType::Grid,
                                                             AccelType::Octree};

/// The scaling chart (core/measure/scaling.h): the scene's mesh repeated 1, 2, 4, ...
/// times up to max_triangles, each scene rasterized (OpenGL and the CPU z-buffer) and
/// ray cast through each of `structures`, frame times on log-log axes.
struct ScalingSettings {
    bool open = false;
    double max_triangles = 4e6;                         ///< the biggest scene (1e4 .. 2e7)
    std::vector<AccelType> structures{AccelType::Bvh};  ///< the ray casts plotted: of kScalingStructures
    bool operator==(const ScalingSettings&) const = default;
};

/// The ray caster's light (core/render/lighting.h): the headlight (a light at the
/// eye) unless a point light is asked for, by a position or by shadows or reflections.
struct LightSettings {
    bool shadows = false;      ///< a shadow ray from every hit to the light (any-hit)
    bool reflections = false;  ///< one bounce off the scene's mirror triangles
    std::optional<Vec3d> position;  ///< empty: default_light(the scene's bounds)
    bool point_light() const { return shadows || reflections || position.has_value(); }
    bool operator==(const LightSettings&) const = default;
};

/// Where the point light is: its position, or the default one of a scene with `bounds`.
Vec3d light_position(const LightSettings& light, const Aabb& bounds);

/// The lighting the ray caster shades `mesh` (whose box is `bounds`) with under
/// `light`; none: the headlight.
std::optional<Lighting> lighting_for(const LightSettings& light, const Mesh& mesh, const Aabb& bounds);

struct AppState {
    std::string scene = "builtin:cube";  ///< "builtin:NAME?k=v" or an OBJ path
    /// A moving scene (builtin:moving, builtin:wave) with a binary BVH: each new time
    /// refits the tree of the time before (the same tree, its boxes recomputed) instead
    /// of building anew; a scene loaded at t != 0 (a preset) refits the t = 0 build.
    bool refit_bvh = false;
    /// The structure and its build parameters; the window starts with a BVH
    /// (a preset can start from naive).
    AccelConfig accel = bvh_config_default();
    OverlaySettings overlay;
    /// The camera; empty means "the scene's default view": the direction of
    /// default_camera() (core/render/camera.h), at the distance that fits the
    /// scene in the 3D view (frame_bounds), filled in when the scene has loaded.
    std::optional<CameraParams> camera;
    ViewSettings view;
    LightSettings light;
    BuildStepSettings build_step;
    StepperSettings stepper;
    NearestSettings nearest;
    ComparisonSettings comparison;
    TwoBvhsSettings two_bvhs;
    ScalingSettings scaling;
};

/// The structure part of the JSON form (what AppState's "structure" holds).
nlohmann::json accel_config_json(const AccelConfig& config);

/// JSON form (every field optional when reading: missing ones keep their defaults).
nlohmann::json to_json(const AppState& state);
/// Reads a state; errors are one line naming the field.
Expected<AppState> app_state_from_json(const nlohmann::json& json);

/// Reads a state (a preset, a saved view) from a JSON file. Errors are one line
/// naming the file and the problem: cannot read, not JSON (with line and
/// column), or the field that is wrong.
/// A relative OBJ path in "scene" is taken relative to the file's directory when
/// a file exists there (a preset can name a mesh beside the repository, e.g.
/// "../../../shared/assets/bunny.obj" from assets/presets/); otherwise it is kept
/// as written (relative to the working directory). Built-ins are unchanged.
Expected<AppState> load_app_state_file(const std::string& path);

/// load_app_state_file, then the structure it names checked as the build will
/// (validate(AccelConfig)): for the window, which uses a loaded state as it is. (The
/// command line checks after its flags are applied: they may replace a bad value.)
Expected<AppState> load_app_state_file_checked(const std::string& path);

}  // namespace accelviz
