#include "app/gl/gpu_ray_caster.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "core/render/frame.h"

namespace accelviz {

namespace {

/// Words the shader writes per pixel (bvh_traversal.comp, binding 4).
constexpr size_t kWords = 6;

/// Fills buffer `buffer` with `bytes` bytes (at least one word: GL rejects empty stores).
void store(const GlBuffer& buffer, const void* data, size_t bytes) {
    static const uint32_t kZero = 0;
    gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, buffer.id());
    gl.BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bytes ? bytes : 4), bytes ? data : &kZero, GL_STATIC_DRAW);
}

}  // namespace

Expected<std::unique_ptr<GpuRayCaster>> GpuRayCaster::create() {
    auto program = ShaderProgram::compute_from_embedded("bvh_traversal.comp");
    if (!program) return Error{program.error()};
    std::unique_ptr<GpuRayCaster> caster(new GpuRayCaster());
    caster->program_ = std::move(*program);
    GLint limit = 0;
    gl.GetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &limit);
    caster->max_buffer_bytes_ = limit > 0 ? size_t(limit) : size_t(1) << 27;  // (the spec's minimum is 16 MiB)
    return caster;
}

std::optional<Error> GpuRayCaster::upload(const Bvh& bvh) {
    static_assert(sizeof(BvhNode) == 8 * sizeof(uint32_t), "the shader reads a node as 8 words");
    static_assert(sizeof(Triangle) == 9 * sizeof(float), "the shader reads a triangle as 9 floats");
    const size_t largest = std::max(bvh.nodes.size() * sizeof(BvhNode), bvh.triangles.size() * sizeof(Triangle));
    if (largest > max_buffer_bytes_)
        return Error{"the BVH's arrays (" + std::to_string(largest >> 20) + " MiB) exceed this device's storage-buffer " +
                     "limit (" + std::to_string(max_buffer_bytes_ >> 20) + " MiB): too many triangles for the GPU cast"};
    store(nodes_, bvh.nodes.data(), bvh.nodes.size() * sizeof(BvhNode));
    store(triangles_, bvh.triangles.data(), bvh.triangles.size() * sizeof(Triangle));
    store(prim_ids_, bvh.prim_ids.data(), bvh.prim_ids.size() * sizeof(uint32_t));
    node_count_ = int(bvh.nodes.size());
    return std::nullopt;
}

GpuCast GpuRayCaster::cast(const Camera& camera) {
    std::vector<Ray> rays;
    rays.reserve(size_t(camera.width()) * size_t(camera.height()));
    for (int y = 0; y < camera.height(); ++y)
        for (int x = 0; x < camera.width(); ++x) rays.push_back(camera.ray(x, y));
    return cast(rays, camera.width(), camera.height());
}

GpuCast GpuRayCaster::cast(const std::vector<Ray>& given, int width, int height) {
    GpuCast out;
    out.width = width;
    out.height = height;
    const size_t pixels = size_t(out.width) * size_t(out.height);
    // Bands of whole rows, each band's rays (9 floats each) within one storage buffer.
    const size_t row_bytes = size_t(std::max(width, 1)) * 9 * sizeof(float);
    const int band_rows = int(std::clamp<size_t>(max_buffer_bytes_ / row_bytes, 1, size_t(std::max(height, 1))));
    std::vector<uint32_t> words(pixels * kWords);
    std::vector<float> rays;
    for (int y0 = 0; y0 < height; y0 += band_rows) {
        const int rows = std::min(band_rows, height - y0);
        const size_t first = size_t(y0) * size_t(width), count = size_t(rows) * size_t(width);
        rays.assign(count * 9, 0.0f);
        for (size_t i = 0; i < count && first + i < given.size(); ++i) {
            const Ray& ray = given[first + i];
            const Vec3 inv(1.0f / ray.dir.x, 1.0f / ray.dir.y, 1.0f / ray.dir.z);  // as BoxTestRay
            const float values[9] = {ray.origin.x, ray.origin.y, ray.origin.z, ray.dir.x, ray.dir.y,
                                     ray.dir.z,    inv.x,        inv.y,        inv.z};
            std::memcpy(&rays[i * 9], values, sizeof values);
        }
        store(rays_, rays.data(), rays.size() * sizeof(float));
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, results_.id());
        gl.BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(count * kWords * sizeof(uint32_t)), nullptr,
                      GL_DYNAMIC_READ);
        const auto start = std::chrono::steady_clock::now();
        program_.use();
        gl.Uniform2i(program_.uniform("u_size"), width, rows);
        gl.Uniform1i(program_.uniform("u_node_count"), node_count_);
        gl.Uniform3f(program_.uniform("u_background"), kBackground.r, kBackground.g, kBackground.b);
        const GLuint buffers[5] = {nodes_.id(), triangles_.id(), prim_ids_.id(), rays_.id(), results_.id()};
        for (GLuint k = 0; k < 5; ++k) gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, k, buffers[k]);
        gl.DispatchCompute(GLuint((width + 7) / 8), GLuint((rows + 7) / 8), 1);
        gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, results_.id());
        gl.GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(count * kWords * sizeof(uint32_t)),
                            &words[first * kWords]);
        out.gpu_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }

    out.tri.resize(pixels);
    out.t.resize(pixels);
    out.iterations.resize(pixels);
    out.stack_depth.resize(pixels);
    out.tests.resize(pixels);
    out.colour = Image(out.width, out.height);
    for (size_t i = 0; i < pixels; ++i) {
        const uint32_t* w = &words[i * kWords];
        out.tri[i] = w[0];
        std::memcpy(&out.t[i], &w[1], sizeof(float));
        out.colour.pixels[i] = {uint8_t(w[2] & 0xff), uint8_t((w[2] >> 8) & 0xff), uint8_t((w[2] >> 16) & 0xff)};
        out.iterations[i] = w[3];
        out.stack_depth[i] = w[4];
        out.tests[i] = w[5];
    }
    return out;
}

GpuAgreement compare_with_cpu(const GpuCast& gpu, const std::vector<uint32_t>& cpu_tri, const std::vector<float>& cpu_t) {
    GpuAgreement a;
    a.pixels = std::min(gpu.tri.size(), cpu_tri.size());
    for (size_t i = 0; i < a.pixels; ++i) {
        if (gpu.tri[i] != cpu_tri[i]) continue;
        ++a.same_triangle;
        if (gpu.tri[i] == Hit::kNoHit) continue;
        const double diff = std::abs(double(gpu.t[i]) - double(cpu_t[i])) / std::max(1e-30, std::abs(double(cpu_t[i])));
        a.max_relative_t = std::max(a.max_relative_t, diff);
    }
    return a;
}

}  // namespace accelviz
