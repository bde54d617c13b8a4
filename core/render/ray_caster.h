#pragma once
/// The CPU ray caster: one ray per pixel centre (camera contract), parallel over
/// 16x16 tiles with oneTBB.

#include "core/accel/accelerator.h"
#include "core/render/camera.h"
#include "core/render/frame.h"

namespace accelviz {

struct RayCastOptions {
    int threads = 0;            ///< 0 = all cores
    bool count_work = false;    ///< fill Frame::nodes / Frame::tests (CountingObserver)
};

/// Casts every pixel's primary ray through `accel`. `triangles` (by id) are used for shading.
Frame ray_cast(const Accelerator& accel, const std::vector<Triangle>& triangles,
               const Camera& camera, const RayCastOptions& options = {});

}  // namespace accelviz
