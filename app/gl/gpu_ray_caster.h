#pragma once
/// The GPU traversal (the lecture's comparison table: "BVH 与 GPU 并行架构匹配度高",
/// BVHs suit parallel hardware): the binary BVH, flattened as the CPU holds it, traversed
/// by an OpenGL 4.3 compute shader (shaders/bvh_traversal.comp), one invocation per
/// pixel with a fixed stack, algorithm 2. It writes each pixel's triangle, t, colour,
/// how many times its loop ran and how deep its stack got. The rays are the camera's
/// (Camera::ray, made on the CPU), so any difference from the CPU's picture is the
/// traversal's. On llvmpipe (OSMesa, no GPU) the shader runs on the CPU's cores; on a
/// real GPU this is the fast path.

#include <memory>
#include <optional>
#include <vector>

#include "app/gl/gl_objects.h"
#include "app/gl/shader.h"
#include "core/accel/bvh.h"
#include "core/render/camera.h"
#include "core/render/image.h"
#include "core/util/expected.h"

namespace accelviz {

/// One picture cast by the GPU: per pixel, row-major, top row first.
struct GpuCast {
    int width = 0, height = 0;
    std::vector<uint32_t> tri;         ///< the triangle hit (Hit::kNoHit: none)
    std::vector<float> t;              ///< its distance (inf: none)
    Image colour;                      ///< headlight-shaded, the CPU ray caster's colours
    std::vector<uint32_t> iterations;  ///< times the invocation's loop ran (nodes visited)
    std::vector<uint32_t> stack_depth;  ///< the deepest its stack got
    std::vector<uint32_t> tests;       ///< triangle tests
    double gpu_ms = 0;                 ///< dispatch to results read back (the ray upload excluded)
};

class GpuRayCaster {
public:
    /// Compiles the compute shader in the current context; an error if the context is
    /// below OpenGL 4.3 or the driver rejects the shader.
    static Expected<std::unique_ptr<GpuRayCaster>> create();
    /// Uploads `bvh` (a binary BVH): its nodes, leaf-ordered triangles and prim ids. An
    /// error when an array is larger than the device's storage-buffer limit.
    std::optional<Error> upload(const Bvh& bvh);
    /// Casts the camera's rays, one per pixel, row-major (the context current). Needs upload() first.
    GpuCast cast(const Camera& camera);
    /// Casts `rays` (width x height of them, in any order: the answers come back in it;
    /// `colour` is a picture only when they are row-major). In bands of rows, each within
    /// the device's storage-buffer limit.
    GpuCast cast(const std::vector<Ray>& rays, int width, int height);

private:
    GpuRayCaster() = default;
    ShaderProgram program_;
    GlBuffer nodes_, triangles_, prim_ids_, rays_, results_;
    int node_count_ = 0;
    size_t max_buffer_bytes_ = 0;  ///< GL_MAX_SHADER_STORAGE_BLOCK_SIZE
};

/// The GPU's answers against the CPU's for the same pixels: how many name the same
/// triangle, and the largest relative difference of t where they do.
struct GpuAgreement {
    size_t pixels = 0, same_triangle = 0;
    double max_relative_t = 0;
    double same_share() const { return pixels ? double(same_triangle) / double(pixels) : 1.0; }
};
GpuAgreement compare_with_cpu(const GpuCast& gpu, const std::vector<uint32_t>& cpu_tri, const std::vector<float>& cpu_t);

}  // namespace accelviz
