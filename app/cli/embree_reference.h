#pragma once
/// Embree 3 as a production reference for `bench --reference embree` (only when
/// CMake found Embree: ACCELVIZ_HAVE_EMBREE). Its high-quality BVH over the same
/// triangles, traced with rtcIntersect1, one ray per call, on the same rays.

#include <memory>
#include <string>
#include <vector>

#include "app/cli/ray_batch.h"
#include "core/geometry/mesh.h"

namespace accelviz::cli {

class EmbreeReference {
public:
    /// A device limited to `threads` threads (0 = Embree's default, all cores).
    explicit EmbreeReference(int threads);
    ~EmbreeReference();
    EmbreeReference(const EmbreeReference&) = delete;
    EmbreeReference& operator=(const EmbreeReference&) = delete;

    /// Builds (or rebuilds) the scene over `mesh`; returns the wall time in ms.
    double build(const Mesh& mesh);
    /// Closest hit of every ray into `results` (primID, tfar), on `threads` threads.
    void trace(const std::vector<Ray>& rays, int threads, RayResults& results) const;
    /// "Embree 3.13.5".
    static std::string version();

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace accelviz::cli
