#include "app/cli/embree_reference.h"

#include <stdexcept>

#ifdef ACCELVIZ_HAVE_EMBREE

#include <chrono>
#include <stdexcept>

#include <embree3/rtcore.h>

namespace accelviz::cli {

bool embree_available() { return true; }

struct EmbreeReference::State {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::string last_error;  ///< Embree's own words for its last error (rtcSetDeviceErrorFunction)
};

EmbreeReference::EmbreeReference(int threads, int bvh_width)
    : state_(std::make_unique<State>()), bvh_width_(bvh_width) {
    if (bvh_width != 0 && bvh_width != 4 && bvh_width != 8)
        throw std::invalid_argument("Embree builds BVHs of 4 or 8 children per node, not " + std::to_string(bvh_width));
    std::string config = "threads=" + std::to_string(threads > 0 ? threads : 0);
    // Embree's own names for "triangles in a BVH of N-wide nodes, four triangles per leaf
    // record" (what it picks by itself: bvh8.triangle4 with AVX, bvh4.triangle4 without)
    // and for the builder its high-quality setting uses by default (SAH with spatial
    // splits), which naming an accel would otherwise replace by plain SAH.
    if (bvh_width != 0)
        config += ",tri_accel=bvh" + std::to_string(bvh_width) + ".triangle4,tri_builder=sah_fast_spatial";
    state_->device = rtcNewDevice(config.c_str());
    if (!state_->device) throw std::runtime_error("Embree: cannot create a device");
    rtcSetDeviceErrorFunction(
        state_->device,
        [](void* user, RTCError, const char* message) {
            static_cast<State*>(user)->last_error = message ? message : "";
        },
        state_.get());
}

EmbreeReference::~EmbreeReference() {
    if (state_->scene) rtcReleaseScene(state_->scene);
    if (state_->device) rtcReleaseDevice(state_->device);
}

std::string EmbreeReference::bvh_description() const {
    if (bvh_width_ != 0) return std::to_string(bvh_width_) + "-wide";
    // Embree 3 picks 8-wide for triangles where it can use AVX (CPU and its own build
    // allowing), else 4-wide; it does not say which through its API.
#if defined(__x86_64__) || defined(__i386__)
    if (__builtin_cpu_supports("avx")) return "8-wide (Embree's choice on CPUs with AVX, like this one)";
#endif
    return "4-wide (Embree's choice without AVX)";
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
    if (const RTCError error = rtcGetDeviceError(state_->device); error != RTC_ERROR_NONE)
        throw std::runtime_error("Embree could not build its BVH (" + bvh_description() + "): " +
                                 (state_->last_error.empty() ? "error code " + std::to_string(int(error))
                                                             : state_->last_error));
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
#else  // no Embree in this build: bench says so before it would construct one

namespace accelviz::cli {

bool embree_available() { return false; }

struct EmbreeReference::State {};

EmbreeReference::EmbreeReference(int, int) {
    throw std::runtime_error("this build has no Embree (CMake did not find embree 3)");
}
EmbreeReference::~EmbreeReference() = default;
std::string EmbreeReference::bvh_description() const { return {}; }
double EmbreeReference::build(const Mesh&) { return 0; }
void EmbreeReference::trace(const std::vector<Ray>&, int, RayResults&) const {}
std::string EmbreeReference::version() { return {}; }

}  // namespace accelviz::cli
#endif  // ACCELVIZ_HAVE_EMBREE
