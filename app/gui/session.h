#pragma once
/// What the window holds beside AppState while it runs: the loaded scene (or
/// the one being loaded), its GPU copies, the last message for the user, and the
/// panels' own state. AppState says what to show; Session has the things it is
/// shown from. Both the window and headless renders keep one and hand it to
/// draw_frame(). Destroy it while its GL context is still alive.

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <array>
#include <vector>

#include "app/gl/renderer.h"
#include "app/gui/app_state.h"
#include "app/gui/build_stepper.h"
#include "app/gui/comparison_panel.h"
#include "app/gui/scaling_panel.h"
#include "app/gui/two_bvhs_panel.h"
#include "app/gui/panels.h"
#include "app/gui/presets.h"
#include "app/gui/ray_cast_view.h"
#include "app/gui/surface_cast.h"
#include "app/gui/scene_loader.h"
#include "app/gui/slice_view.h"
#include "app/gui/gpu_cast_view.h"
#include "app/gui/nearest_panel.h"
#include "app/gui/stepper_panel.h"
#include "app/gui/structure_overlay.h"
#include "app/gui/ui_style.h"
#include "app/gui/moving_box_budget.h"
#include "app/gui/view_cache.h"

namespace accelviz {

struct Session {
    /// Split view, left half "opengl-depth": OpenGL's depth buffer read back as
    /// ray distances t, grey on the ray cast's scale (made lazily, with GL current).
    std::unique_ptr<Texture> gl_depth_texture;
    /// The scene on screen (null until the first load finishes). Immutable:
    /// a new load replaces the pointer, never the contents.
    std::shared_ptr<const LoadedScene> scene;
    SceneLoader loader;
    /// When the load under way finishes: keep AppState's camera (a preset or
    /// the command line set it) instead of the new scene's default view.
    bool keep_camera_on_load = false;

    /// The camera was just reset to the scene's default view: the next frame
    /// frames the scene for the view's actual aspect ratio (frame_bounds).
    bool frame_pending = false;

    /// The last thing the user should know: a load error ("keeping the previous
    /// scene"). Empty: nothing to say.
    std::string message;
    bool message_is_error = true;  ///< false: a notice ("saved ..."), shown in neutral colours

    /// A screenshot of the next frame goes to this PNG path (then cleared).
    std::string screenshot_path;

    // GPU copies of `scene` (made on the UI thread, which owns the context).
    std::unique_ptr<BoxBuffer> bounds_buffer;
    uint64_t scene_generation = 0;     ///< counts set_scene() calls
    uint64_t uploaded_generation = 0;  ///< the generation bounds_buffer holds
    /// The mesh's GPU copy, uploaded the first time a frame rasterizes it (call on
    /// the GL thread, with a scene). A scene only ever ray cast (Draw with: auto picks
    /// the ray caster for big meshes) never needs one: at 10M triangles the upload
    /// takes about a second on llvmpipe, and the driver keeps its own copy.
    MeshBuffer& mesh_for_raster();
    std::unique_ptr<MeshBuffer> mesh_buffer;  ///< made by mesh_for_raster(): draw through that
    uint64_t mesh_generation = 0;             ///< the generation mesh_buffer holds

    // The structure overlay of `scene` (and its GPU copy), remade when the scene
    // or the overlay settings change.
    StructureOverlay overlay;
    std::unique_ptr<BoxBuffer> overlay_boxes;
    std::unique_ptr<ColouredBuffer> overlay_quads;
    uint64_t overlay_generation = 0;   ///< scene generation the overlay is of (0: none)
    OverlaySettings overlay_settings;  ///< the settings it was made with

    /// The CPU ray caster's picture for the split view.
    RayCastView ray_cast;

    /// The camera's motion: a view that moves is drawn lighter (a quarter of the
    /// ray-cast mesh's pixels, the overlay's shallow levels only) until the camera
    /// has been still for kCameraStillSeconds.
    static constexpr double kCameraStillSeconds = 0.2;
    /// While the camera moves, the overlay draws whole shallow levels up to a budget
    /// that follows the frame time; every box once it is still.
    MovingBoxBudget moving_boxes;
    CameraParams last_camera;
    uint64_t last_scene_generation = 0;  ///< a new scene (a moving scene's next time) counts as motion too
    std::chrono::steady_clock::time_point camera_moved_at{};
    bool camera_moving = false;  ///< this frame's view is drawn lighter

    /// The 3D view's last still picture, drawn again while nothing it shows changes.
    ViewCache view_cache;

    /// "Draw with: ray cast": the 3D view's mesh from the CPU ray caster.
    SurfaceCast surface_cast;
    /// What drew the mesh in the last frame (the status line says which), and whether
    /// "ray cast" was refused because a brute-force cast of the view would take minutes.
    bool mesh_ray_cast = false;
    bool brute_force_cast_refused = false;
    /// "Draw with: auto": the last rasterized mesh's time in ms (to glFinish), the
    /// scene generation it was measured on (0: not measured) and when.
    double raster_mesh_ms = 0;
    uint64_t raster_measured_scene = 0;
    std::chrono::steady_clock::time_point raster_measured_at{};
    double raster_ms_per_triangle = 0;  ///< from the last measurement, for a scene not yet measured

    /// The construction stepper: the recorded BVH build and the SAH chart of the step shown.
    BuildStepper build_stepper;

    /// The comparison panel: every structure measured on the scene (on a worker).
    ComparisonPanel comparison;
    /// The two-BVHs panel: the scene's BVH by two builders, side by side (on a worker).
    TwoBvhsPanel two_bvhs;
    /// The scaling panel: frame time against triangles, the mesh repeated (on a worker).
    ScalingPanel scaling;
    /// Which right panels were open in the previous frame (two BVHs, comparison, scaling,
    /// ray stepper, nearest-point stepper, construction stepper): draw_frame keeps the one
    /// switched on last.
    std::array<bool, 6> right_panel_was_open{};

    UiStyle style;
    bool dragging_view = false;  ///< a mouse drag that started in the 3D view
    bool dragging_light = false;  ///< ... on the point light's marker: it moves the light
    std::vector<std::array<float, 2>> light_markers;  ///< where the light's markers were drawn last (window pixels)
    bool dragging_query = false;  ///< ... on the nearest-point query point's marker: it moves the point
    std::vector<std::array<float, 2>> query_markers;  ///< where the query point's marker was drawn last

    /// Lecture mode (L, or `accelviz --lecture`): the window full screen, no panels,
    /// text at projector scale, the preset's number and title in a caption bar.
    struct LectureMode {
        bool on = false;
        bool caption = true;  ///< the caption bar (C hides it)
        bool blank = false;   ///< B: a black screen, to talk over
    };
    LectureMode lecture;

    ScenePanel scene_panel;
    StructurePanel structure_panel;
    StatsPanel stats_panel;
    ViewPanel view_panel;
    StatsBar stats_bar;
    HelpWindow help_window;
    /// assets/presets: PageDown / PageUp and the Scene panel's list.
    PresetList presets;
    NearestPanel nearest;
    SliceView slice;  ///< the inside/outside slice (on a worker)
    /// The split view's right half cast by the GPU (View: Ray cast by GPU), and whether
    /// this frame shows it (else the CPU's picture: the GPU cannot, or another view).
    GpuCastView gpu_cast;
    bool gpu_cast_shown = false;
    std::string gpu_cast_reason;  ///< why the GPU does not cast it (the label says so)
    StepperPanel stepper;  ///< last: its worker may hold the scene's mesh

    /// Starts loading `source` with the state's structure (on the worker).
    void open_scene(const AppState& state, const std::string& source, bool keep_camera = false);
    /// A moving scene at time t (scene_at_time of the current one, on the worker): its
    /// BVH refitted to the moved mesh when `refit` (and the structure is a binary BVH),
    /// else the state's structure built anew. The camera stays.
    void open_scene_at_time(const AppState& state, double t, bool refit);
    /// Starts building the state's structure over the current mesh (on the
    /// worker); the camera stays.
    void rebuild_structure(const AppState& state);
    /// Uses the structure in `path` (docs/structure-format.md; a student's tree) over
    /// the current mesh instead of building one: read and checked on the worker.
    void use_structure_file(AppState& state, const std::string& path);
    /// Takes a finished load, if any: swaps the scene in and updates the state's
    /// scene and camera; on failure sets `message` and keeps everything as it was.
    void take_finished_load(AppState& state);
    /// Swaps in a loaded scene (what take_finished_load does on success).
    void set_scene(AppState& state, std::shared_ptr<const LoadedScene> loaded, bool keep_camera);
    /// Switches to a saved state: reloads the scene or rebuilds the structure
    /// only where they differ (on the worker), takes the rest at once.
    void apply_state(AppState& state, const AppState& loaded);
    /// Shows a notice or an error in the view.
    void notify(std::string text, bool is_error);
    /// True while a worker runs or has a result to hand over, or a preset's caption
    /// is up (the window keeps drawing frames until then).
    bool has_pending_work() const { return !pending_work().empty(); }
    /// What has_pending_work() waits for, by name ("loader", "caption", "ray_cast",
    /// "build_stepper", "stepper", "comparison", "two_bvhs", "fill_order" while it plays): the UI
    /// snapshot lists them.
    std::vector<const char*> pending_work() const;
    /// Makes the GPU copies match `scene` and the overlay match `settings`
    /// (call on the GL thread).
    void upload_to_gpu(const OverlaySettings& settings);
};

}  // namespace accelviz
