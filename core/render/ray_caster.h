#pragma once
/// The CPU ray caster: one ray per pixel centre (camera contract), parallel over
/// 16x16 tiles with oneTBB.

#include "core/accel/accelerator.h"
#include "core/render/camera.h"
#include "core/util/work_progress.h"
#include "core/render/frame.h"

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
};

/// Casts every pixel's primary ray through `accel`. `triangles` (by id) are used for shading.
Frame ray_cast(const Accelerator& accel, const TriangleArray& triangles,
               const Camera& camera, const RayCastOptions& options = {});

}  // namespace accelviz
