#pragma once
/// The 3D view's last picture, kept while nothing it is drawn from changes. The
/// window draws a few frames after every event (a mouse move over a panel, a
/// hover), and with a big overlay (a BVH's 77k boxes, a million line segments)
/// each such frame would redraw every box on a software rasterizer, a third of a
/// second, for a picture that did not change: the panels would answer the mouse
/// late. So once a still view is drawn in full, its pixels are read back into a
/// texture, and later frames with the same inputs draw that texture instead.
///
/// The key is everything the 3D view is drawn from (its size, camera, the view,
/// overlay and light settings, the scene and the ray-cast picture shown); a view
/// that draws from anything else (a stepper, the slice, the split view, a moving
/// camera) is never kept. The copy restores the colour only: nothing after the 3D
/// view reads its depth in a window frame (headless renders, which do, keep no
/// picture unless a test asks for it).

#include <cstdint>
#include <memory>
#include <optional>

#include "app/gl/texture.h"
#include "app/gl/view3d.h"
#include "app/gui/app_state.h"
#include "app/gui/surface_cast.h"
#include "core/render/camera.h"

namespace accelviz {

class Renderer;

class ViewCache {
public:
    /// What a picture of the 3D view is drawn from.
    struct Key {
        int frame_width = 0, frame_height = 0;
        ViewRect rect;
        CameraParams camera;
        ViewSettings view;
        OverlaySettings overlay;
        LightSettings light;
        uint64_t scene_generation = 0;
        bool mesh_ray_cast = false;
        std::optional<SurfaceCast::Key> ray_cast_picture;  ///< the picture shown, when the ray caster draws the mesh
        bool operator==(const Key&) const = default;
    };

    /// A full draw of the view is kept only if the last one took at least this long:
    /// the read-back (a few ms) would slow down a view that is quick to redraw.
    static constexpr double kWorthKeepingMs = 25.0;

    /// Draws the kept picture into key.rect if it was drawn from `key`: true, and
    /// nothing else of the 3D view needs drawing this frame.
    bool draw(const Key& key, Renderer& renderer);
    /// After a full draw of the view from `key`: keeps its pixels if the last full
    /// draw took `last_full_ms` >= the threshold (tests lower it), else forgets.
    void keep(const Key& key, Renderer& renderer, double last_full_ms);
    /// The view is drawn from something the key does not hold: forget the picture.
    void forget() { key_.reset(); }

    /// How many frames drew the kept picture (what a test checks to know it was used).
    uint64_t hits() const { return hits_; }
    /// The threshold keep() uses (tests set 0: keep every full draw).
    double worth_keeping_ms = kWorthKeepingMs;

private:
    std::optional<Key> key_;
    std::unique_ptr<Texture> picture_;  ///< made by the first keep(), with GL current
    uint64_t hits_ = 0;
};

}  // namespace accelviz
