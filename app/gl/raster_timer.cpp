#include "app/gl/raster_timer.h"

#include <chrono>

#include "app/gl/view3d.h"

namespace accelviz {

double RasterTimer::frame_ms(const Mesh& mesh, const Camera& camera) {
    if (uploaded_ != &mesh || uploaded_triangles_ != mesh.triangle_count()) {
        buffer_.upload(mesh);
        uploaded_ = &mesh;
        uploaded_triangles_ = mesh.triangle_count();
    }
    const ViewRect rect{0, 0, camera.width(), camera.height()};
    const View3D view = make_view3d(camera.params(), rect, mesh.bounds());
    renderer_.finish();  // what was queued before is not this frame's
    const auto start = std::chrono::steady_clock::now();
    renderer_.begin_frame(rect.width, rect.height, Rgb{255, 255, 255});
    renderer_.begin_view(view);
    renderer_.draw_mesh(buffer_, MeshStyle{});
    renderer_.finish();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace accelviz
