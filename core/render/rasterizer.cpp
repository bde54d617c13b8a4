#include "core/render/rasterizer.h"

namespace accelviz {

// Placeholder until the real rasterizer lands.
Frame rasterize(const Mesh&, const Camera& camera, RasterStats*) { return Frame(camera.width(), camera.height()); }

}  // namespace accelviz
