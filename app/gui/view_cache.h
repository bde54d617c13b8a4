#pragma once
/// The 3D view's last picture, kept while nothing it is drawn from changes. The
/// window draws a few frames after every event (a mouse move over a panel, a
/// hover), and with a big overlay (a BVH's 77k boxes, a million line segments)
/// each such frame would redraw every box on a software rasterizer, hundreds of
/// milliseconds, for a picture that did not change: the panels would answer the
/// mouse late. So once a still view is drawn in full, its pixels are copied into a
/// texture, and later frames with the same inputs draw that texture instead.
///
/// Progressive: a still view that is slow to draw and has more boxes than one frame
/// should draw (kStillBoxesPerFrame) draws them a share per frame: the first frame
/// the mesh and the first boxes, and its depth buffer (the mesh's alone: boxes write
/// no depth) is kept with the picture; each next frame draws the picture so far
/// with that depth, then the next boxes, until every box is in the picture. Boxes are
/// drawn in the same order as in one frame, so the finished picture is the one-frame
/// picture, pixel for pixel, and no frame stops the window for long.
///
/// The key is everything the 3D view is drawn from (its size, camera, the view,
/// overlay and light settings, the scene and the ray-cast picture shown); a view
/// that draws from anything else (a stepper, the slice, the split view, a moving
/// camera) is never kept. A whole picture is drawn back as colours only: nothing
/// after the 3D view reads its depth in a window frame (headless renders, which do,
/// keep no picture unless a test asks for it); only a picture under way is drawn
/// with its depth, for the boxes still to come.

#include <cstdint>
#include <memory>
#include <optional>

#include "app/gl/texture.h"
#include "app/gl/view3d.h"
#include "app/gui/app_state.h"
#include "app/gui/moving_box_budget.h"
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
    /// the copy (a few ms) would slow down a view that is quick to redraw.
    static constexpr double kWorthKeepingMs = 25.0;
    /// Boxes a still view draws per frame when it draws them over several: the
    /// moving camera's first budget (MovingBoxBudget::kStartBoxes), so that the first
    /// such frame, which draws the mesh too, takes no longer than a frame while the
    /// camera moves on a renderer slow enough to draw a picture in shares (measured:
    /// docs/performance.md).
    static constexpr size_t kStillBoxesPerFrame = MovingBoxBudget::kStartBoxes;

    /// A frame begins; the previous one took `previous_frame_ms` (0: unknown). The time
    /// of a frame that drew the view in full says whether the next full draw is kept.
    void start_frame(double previous_frame_ms) {
        if (last_frame_full_) last_full_ms_ = previous_frame_ms;
    }
    /// Draws the kept picture into key.rect if it was drawn from `key` and is whole:
    /// true, and nothing else of the 3D view needs drawing this frame.
    bool draw(const Key& key, Renderer& renderer);

    /// What a frame that draws the view itself draws of its overlay boxes.
    struct Share {
        bool goes_on = false;     ///< a picture under way: picture() with depth(), then the boxes below
        bool keep = false;        ///< the view drawn this frame is kept (finish_frame)
        size_t first = 0;         ///< the first overlay box this frame draws
        size_t count = SIZE_MAX;  ///< how many (SIZE_MAX: all the rest)
    };
    /// A frame draws the view from `key` (`keepable`: from the key alone), with
    /// `boxes_total` overlay boxes over a mesh that hides what lies behind it (`opaque`;
    /// an x-ray view is drawn in one frame): it goes on with the picture under way,
    /// starts one in shares, draws the view in full and keeps it, or only draws it.
    Share plan_frame(const Key& key, bool keepable, size_t boxes_total, bool opaque) const;
    /// After the view is drawn as `share` said: keeps its pixels (and, for the first of
    /// several shares, its depth), or forgets the picture.
    void finish_frame(const Key& key, const Share& share, size_t boxes_total, Renderer& renderer);
    /// A picture is under way (the window keeps drawing frames until it is whole).
    bool drawing_on() const { return key_ && boxes_in_picture_ < boxes_total_; }
    const Texture& picture() const { return *picture_; }
    /// The depth buffer of a picture under way's first frame (depth-buffer values).
    const Texture& depth() const { return *depth_; }
    /// The view is drawn from something the key does not hold, or not drawn: forget
    /// the picture.
    void forget() { key_.reset(); }

    /// How many frames drew the whole kept picture (what a test checks to know it was used).
    uint64_t hits() const { return hits_; }
    /// A full draw is kept if the last one took this long (tests set 0: keep every one).
    double worth_keeping_ms = kWorthKeepingMs;
    /// Boxes per frame of a progressive picture (tests set fewer).
    size_t boxes_per_frame = kStillBoxesPerFrame;

private:
    bool holds(const Key& key) const { return key_ && *key_ == key; }

    std::optional<Key> key_;
    std::unique_ptr<Texture> picture_;  ///< made by the first keep(), with GL current
    std::unique_ptr<Texture> depth_;    ///< made by the first picture drawn in shares
    size_t boxes_in_picture_ = 0, boxes_total_ = 0;
    bool last_frame_full_ = false;  ///< the last frame drew the view in full (not from the picture)
    double last_full_ms_ = 0;       ///< the time of the last frame that did (0: unknown)
    uint64_t hits_ = 0;
};

}  // namespace accelviz
