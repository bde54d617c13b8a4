#pragma once
/// Embree 3 as a production reference for `bench --reference embree`: its
/// high-quality BVH over the same triangles, traced with rtcIntersect1, one ray per
/// call, on the same rays. Available when CMake found Embree (ACCELVIZ_HAVE_EMBREE);
/// otherwise embree_available() is false and constructing one throws.
///
/// Embree's BVH is not binary: by default it picks 8 children per node on a CPU with
/// AVX (BVH8: a node's eight boxes are tested together, one per SIMD lane) and 4
/// without. `bvh_width` can ask for either, so the price of a wider node is measured.

#include <memory>
#include <string>
#include <vector>

#include "app/cli/ray_batch.h"
#include "core/geometry/mesh.h"

namespace accelviz::cli {

/// Whether this build has Embree.
bool embree_available();

class EmbreeReference {
public:
    /// A device limited to `threads` threads (0 = Embree's default, all cores),
    /// building BVHs of `bvh_width` children per node (4 or 8; 0 = Embree's choice).
    explicit EmbreeReference(int threads, int bvh_width = 0);
    ~EmbreeReference();
    EmbreeReference(const EmbreeReference&) = delete;
    EmbreeReference& operator=(const EmbreeReference&) = delete;

    /// The BVH it builds, for people: "4-wide", "8-wide (Embree's choice on CPUs with AVX, ...)".
    std::string bvh_description() const;
    /// Builds (or rebuilds) the scene over `mesh`; returns the wall time in ms.
    /// Throws std::runtime_error if Embree reports an error.
    double build(const Mesh& mesh);
    /// Closest hit of every ray into `results` (primID, tfar), on `threads` threads.
    void trace(const std::vector<Ray>& rays, int threads, RayResults& results) const;
    /// "Embree 3.13.5".
    static std::string version();

private:
    struct State;
    std::unique_ptr<State> state_;
    int bvh_width_ = 0;
};

}  // namespace accelviz::cli
