// Compiled only when CMake found Embree (see app/CMakeLists.txt).
#ifdef ACCELVIZ_HAVE_EMBREE
#include "app/cli/embree_reference.h"

#include <chrono>
#include <stdexcept>

#include <embree3/rtcore.h>

namespace accelviz::cli {

struct EmbreeReference::State {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
};

EmbreeReference::EmbreeReference(int threads) : state_(std::make_unique<State>()) {
    const std::string config = "threads=" + std::to_string(threads > 0 ? threads : 0);
    state_->device = rtcNewDevice(config.c_str());
    if (!state_->device) throw std::runtime_error("Embree: cannot create a device");
}

EmbreeReference::~EmbreeReference() {
    if (state_->scene) rtcReleaseScene(state_->scene);
    if (state_->device) rtcReleaseDevice(state_->device);
}

std::string EmbreeReference::version() {
    return "Embree " + std::to_string(RTC_VERSION_MAJOR) + "." + std::to_string(RTC_VERSION_MINOR) + "." +
           std::to_string(RTC_VERSION_PATCH);
}

double EmbreeReference::build(const Mesh& mesh) {
    const auto start = std::chrono::steady_clock::now();
    if (state_->scene) rtcReleaseScene(state_->scene);
    state_->scene = rtcNewScene(state_->device);
    rtcSetSceneBuildQuality(state_->scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geometry = rtcNewGeometry(state_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh.positions.size()));
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        vertices[3 * i + 0] = mesh.positions[i].x;
        vertices[3 * i + 1] = mesh.positions[i].y;
        vertices[3 * i + 2] = mesh.positions[i].z;
    }
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), mesh.indices.size()));
    for (size_t i = 0; i < mesh.indices.size(); ++i)
        for (int c = 0; c < 3; ++c) indices[3 * i + c] = mesh.indices[i][c];
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(state_->scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(state_->scene);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void EmbreeReference::trace(const std::vector<Ray>& rays, int threads, RayResults& results) const {
    RTCScene scene = state_->scene;
    for_each_ray_chunk(rays.size(), threads, [&](size_t begin, size_t end) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (size_t i = begin; i < end; ++i) {
            const Ray& ray = rays[i];
            RTCRayHit rh;
            rh.ray.org_x = ray.origin.x;
            rh.ray.org_y = ray.origin.y;
            rh.ray.org_z = ray.origin.z;
            rh.ray.dir_x = ray.dir.x;
            rh.ray.dir_y = ray.dir.y;
            rh.ray.dir_z = ray.dir.z;
            rh.ray.tnear = ray.t_min;
            rh.ray.tfar = ray.t_max;
            rh.ray.time = 0;
            rh.ray.mask = 0xffffffffu;
            rh.ray.id = 0;
            rh.ray.flags = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &context, &rh);
            if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
                results.t[i] = rh.ray.tfar;
                results.tri[i] = rh.hit.primID;
            } else {
                results.t[i] = kInfinity;
                results.tri[i] = Hit::kNoHit;
            }
        }
    });
}

}  // namespace accelviz::cli
#endif  // ACCELVIZ_HAVE_EMBREE
