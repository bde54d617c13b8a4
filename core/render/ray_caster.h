#pragma once
/// The CPU ray caster: one ray per pixel centre (camera contract), parallel over
/// 16x16 tiles with oneTBB.

#include "core/accel/accelerator.h"
#include "core/geometry/mesh.h"
#include "core/render/camera.h"
#include "core/util/work_progress.h"
#include "core/render/frame.h"
#include "core/render/lighting.h"

namespace accelviz {

/// The threads a request for `requested` gets: 0 means all cores, and more than the
/// cores oneTBB can use are capped to them (it would run no more, and print a warning).
int effective_threads(int requested);

struct RayCastOptions {
    int threads = 0;            ///< 0 = all cores; capped by effective_threads()
    bool count_work = false;    ///< fill Frame::nodes / Frame::tests (CountingObserver)
    /// Once cancelled, tiles not started are left as they are (background, no hit):
    /// for a picture nobody wants any more (a newer camera, a closed view).
    const WorkProgress* cancel = nullptr;
    /// A point light, shadow rays and mirrors (lighting.h); null: the headlight alone
    /// (a light at the eye, no secondary rays).
    const Lighting* lighting = nullptr;
};

/// Casts every pixel's primary ray through `accel`. The hit triangle is read from
/// `mesh` (by id) for shading: one triangle per hit pixel, so no copy of the mesh's
/// triangles is made (at 10M triangles such a copy is 500 MB). With a lighting: a
/// shadow ray from each hit to the light (any-hit), and from a mirror one reflection
/// ray (closest-hit), whose hit is shaded with its own shadow ray; one bounce, so a
/// mirror seen in a mirror is shaded as a wall.
Frame ray_cast(const Accelerator& accel, const Mesh& mesh,
               const Camera& camera, const RayCastOptions& options = {});

/// The lesson of the any-hit query: every shadow ray of a picture (one per pixel that
/// sees a lit side; none from mirrors) traced twice over the same segment, as any-hit
/// (stop at the first occluder) and as closest-hit (find the nearest one), counted.
struct ShadowQueryWork {
    uint64_t rays = 0;     ///< shadow rays traced
    uint64_t blocked = 0;     ///< of them, rays any-hit found blocked
    uint64_t disagreed = 0;   ///< rays where any-hit and closest-hit disagree (a bug if not 0)
    Counters any_hit, closest_hit;                  ///< over all the shadow rays
    Counters any_hit_blocked, closest_hit_blocked;  ///< over the blocked ones (where they differ)
};
ShadowQueryWork measure_shadow_queries(const Accelerator& accel, const Mesh& mesh, const Camera& camera,
                                       const Lighting& lighting, int threads = 0);

}  // namespace accelviz
