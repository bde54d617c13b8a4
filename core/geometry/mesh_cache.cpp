#include "core/geometry/mesh_cache.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string_view>
#include <system_error>
#include <vector>

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace accelviz {

namespace {

constexpr char kMagic[8] = {'A', 'V', 'Z', 'M', 'E', 'S', 'H', '\n'};
constexpr uint32_t kVersion = 1;
constexpr uint64_t kEdgeBytes = 1 << 20;  ///< hashed at each end of the OBJ file
constexpr std::string_view kTemporaryInfix = ".tmp.";  ///< a copy being written: NAME.tmp.PID

static_assert(sizeof(Vec3) == 12, "a vertex is stored as three floats");
constexpr uint64_t kTriangleBytes = sizeof(std::array<uint32_t, 3>);
static_assert(kTriangleBytes == 12, "a triangle is stored as three indices");

/// The copy's header, followed by the path's bytes (zero-padded to a multiple of 8,
/// so that the arrays after it are aligned when the file is mapped), the positions
/// and the indices.
struct Header {
    char magic[8];
    uint32_t version;
    uint32_t path_length;
    uint64_t size;
    int64_t mtime_ns;
    uint64_t edge_hash;
    uint64_t vertex_count;
    uint64_t triangle_count;
    uint64_t payload_hash;  ///< of the path, the positions and the indices
};

/// A 64-bit hash of bytes, eight at a time (a multiply-xorshift mix per word): not
/// cryptographic, only to notice a copy that was damaged or belongs to another file.
class Hasher {
public:
    void add(const void* data, size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        size_t i = 0;
        for (; i + 8 <= bytes; i += 8) {
            uint64_t word;
            std::memcpy(&word, p + i, 8);
            mix(word);
        }
        uint64_t tail = 0;
        if (bytes > i) std::memcpy(&tail, p + i, bytes - i);  // (an empty array's data() may be null)
        mix(tail ^ (uint64_t(bytes - i) << 56));
    }
    uint64_t value() const { return h_; }

private:
    void mix(uint64_t word) {
        h_ = (h_ ^ word) * 0x9E3779B97F4A7C15ull;
        h_ ^= h_ >> 29;
    }
    uint64_t h_ = 0xCBF29CE484222325ull;
};

uint64_t hash_of(const std::string& text) {
    Hasher h;
    h.add(text.data(), text.size());
    return h.value();
}

uint64_t padded(uint64_t path_length) { return (path_length + 7) / 8 * 8; }

/// A file mapped read-only into memory (empty if it cannot be).
class MappedFile {
public:
    explicit MappedFile(const std::filesystem::path& file) {
        const int fd = ::open(file.c_str(), O_RDONLY);
        if (fd < 0) return;
        struct stat st;
        if (::fstat(fd, &st) == 0 && st.st_size > 0) {
            void* p = ::mmap(nullptr, size_t(st.st_size), PROT_READ, MAP_PRIVATE, fd, 0);
            if (p != MAP_FAILED) {
                data_ = static_cast<const char*>(p);
                size_ = size_t(st.st_size);
            }
        }
        ::close(fd);
    }
    ~MappedFile() {
        if (data_) ::munmap(const_cast<char*>(data_), size_);
    }
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;
    const char* data() const { return data_; }
    size_t size() const { return size_; }

private:
    const char* data_ = nullptr;
    size_t size_ = 0;
};

uint64_t payload_hash(const std::string& path, const Mesh& mesh) {
    Hasher h;
    h.add(path.data(), path.size());
    h.add(mesh.positions.data(), mesh.positions.size() * sizeof(Vec3));
    h.add(mesh.indices.data(), mesh.indices.size() * sizeof(mesh.indices[0]));
    return h.value();
}

/// Removes the temporary copies (`NAME.tmp.PID`) that processes no longer running left
/// in `dir`: a window closed while it wrote a copy does not wait to remove its file
/// (up to ~240 MB at 10M triangles), and nothing else would. A file whose process is
/// alive, or cannot be asked about, stays.
void remove_stale_temporaries(const std::filesystem::path& dir) {
    std::error_code ec;
    for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        const size_t at = name.rfind(kTemporaryInfix);
        if (at == std::string::npos) continue;
        const char* first = name.data() + at + kTemporaryInfix.size();
        const char* last = name.data() + name.size();
        pid_t pid = 0;
        const auto [parsed_to, error] = std::from_chars(first, last, pid);
        if (error != std::errc() || parsed_to != last || pid <= 0 || pid == ::getpid()) continue;
        if (::kill(pid, 0) == 0 || errno != ESRCH) continue;
        std::error_code removed;
        std::filesystem::remove(it->path(), removed);
    }
}

}  // namespace

std::optional<std::filesystem::path> default_mesh_cache_dir() {
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::filesystem::path(xdg) / "accelviz";
    if (const char* home = std::getenv("HOME"); home && *home)
        return std::filesystem::path(home) / ".cache" / "accelviz";
    return std::nullopt;
}

std::optional<ObjKey> obj_key(const std::string& path) {
    std::error_code ec;
    ObjKey key;
    key.path = std::filesystem::absolute(path, ec).lexically_normal().string();
    if (ec) return std::nullopt;
    if (!std::filesystem::is_regular_file(key.path, ec) || ec) return std::nullopt;
    key.size = std::filesystem::file_size(key.path, ec);
    if (ec) return std::nullopt;
    const auto mtime = std::filesystem::last_write_time(key.path, ec);
    if (ec) return std::nullopt;
    key.mtime_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(mtime.time_since_epoch()).count();
    std::ifstream in(key.path, std::ios::binary);
    if (!in) return std::nullopt;
    std::vector<char> edge(std::min(key.size, kEdgeBytes));
    Hasher h;
    in.read(edge.data(), std::streamsize(edge.size()));
    h.add(edge.data(), size_t(in.gcount()));
    if (key.size > kEdgeBytes) {
        in.seekg(std::streamoff(key.size - edge.size()));
        in.read(edge.data(), std::streamsize(edge.size()));
        h.add(edge.data(), size_t(in.gcount()));
    }
    key.edge_hash = h.value();
    return key;
}

std::filesystem::path mesh_cache_file(const std::filesystem::path& cache_dir, const ObjKey& key) {
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.mesh", static_cast<unsigned long long>(hash_of(key.path)));
    return cache_dir / name;
}

std::optional<Mesh> read_mesh_cache(const std::filesystem::path& file, const ObjKey& key, const std::string& name) {
    // Mapped rather than read: the arrays are copied once, straight into the mesh.
    const MappedFile map(file);
    if (map.size() < sizeof(Header)) return std::nullopt;
    Header h;
    std::memcpy(&h, map.data(), sizeof h);
    if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 || h.version != kVersion) return std::nullopt;
    if (h.path_length != key.path.size() || h.size != key.size || h.mtime_ns != key.mtime_ns ||
        h.edge_hash != key.edge_hash)
        return std::nullopt;
    // The file must be exactly as long as its header says (no truncation, nothing extra).
    const uint64_t size = map.size();
    if (h.vertex_count > size / sizeof(Vec3) || h.triangle_count > size / kTriangleBytes) return std::nullopt;
    const uint64_t positions_at = sizeof h + padded(h.path_length);
    const uint64_t indices_at = positions_at + h.vertex_count * sizeof(Vec3);
    if (size != indices_at + h.triangle_count * kTriangleBytes) return std::nullopt;
    const std::string path(map.data() + sizeof h, h.path_length);
    if (path != key.path) return std::nullopt;
    Mesh mesh;
    mesh.name = name;
    const auto* positions = reinterpret_cast<const Vec3*>(map.data() + positions_at);
    const auto* indices = reinterpret_cast<const std::array<uint32_t, 3>*>(map.data() + indices_at);
    mesh.positions.assign(positions, positions + h.vertex_count);
    mesh.indices.assign(indices, indices + h.triangle_count);
    if (payload_hash(path, mesh) != h.payload_hash) return std::nullopt;
    for (const auto& tri : mesh.indices)
        for (uint32_t i : tri)
            if (i >= h.vertex_count) return std::nullopt;
    return mesh;
}

bool write_mesh_cache(const std::filesystem::path& file, const ObjKey& key, const Mesh& mesh,
                      WorkProgress* progress) {
    std::error_code ec;
    std::filesystem::create_directories(file.parent_path(), ec);
    if (ec) return false;
    remove_stale_temporaries(file.parent_path());
    const size_t position_bytes = mesh.positions.size() * sizeof(Vec3);
    const size_t index_bytes = mesh.indices.size() * kTriangleBytes;
    // The stage: hashing the payload (counted as one pass over it), then writing it.
    start_stage(progress, 2 * uint64_t(position_bytes + index_bytes), "writing the cache copy");
    Header h;
    std::memcpy(h.magic, kMagic, sizeof kMagic);
    h.version = kVersion;
    h.path_length = uint32_t(key.path.size());
    h.size = key.size;
    h.mtime_ns = key.mtime_ns;
    h.edge_hash = key.edge_hash;
    h.vertex_count = mesh.positions.size();
    h.triangle_count = mesh.indices.size();
    h.payload_hash = payload_hash(key.path, mesh);
    advance(progress, position_bytes + index_bytes);
    // A temporary name of this process, renamed into place when complete.
    const std::filesystem::path temp = file.string() + std::string(kTemporaryInfix) + std::to_string(::getpid());
    {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(&h), sizeof h);
        out.write(key.path.data(), std::streamsize(key.path.size()));
        const char zeros[8] = {};
        out.write(zeros, std::streamsize(padded(key.path.size()) - key.path.size()));
        // The payload in pieces, so that a 10M-triangle copy (240 MB) shows progress
        // and can be cancelled.
        constexpr size_t kPiece = size_t(8) << 20;
        const auto write_pieces = [&](const void* data, size_t bytes) {
            const char* p = static_cast<const char*>(data);
            for (size_t done = 0; done < bytes && out && !cancelled(progress); done += kPiece) {
                const size_t n = std::min(kPiece, bytes - done);
                out.write(p + done, std::streamsize(n));
                advance(progress, n);
            }
        };
        write_pieces(mesh.positions.data(), position_bytes);
        write_pieces(mesh.indices.data(), index_bytes);
        out.close();
        if (!out || cancelled(progress)) {
            if (progress) progress->clear_stage_label();
            std::filesystem::remove(temp, ec);
            return false;
        }
    }
    if (progress) progress->clear_stage_label();
    std::filesystem::rename(temp, file, ec);
    if (!ec) return true;
    std::filesystem::remove(temp, ec);
    return false;
}

}  // namespace accelviz
