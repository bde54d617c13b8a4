#pragma once
/// The mesh cache: the first load of an OBJ file writes its triangles as a compact
/// binary copy, and later loads of the same, unchanged file read that copy instead
/// of parsing the text again (a 420 MB OBJ parses in about 20 s; its copy reads in
/// well under a second).
///
/// A copy is used only when everything matches: the file's absolute path, size,
/// modification time and a hash of its first and last MiB (the key), the format
/// version, and a hash of the copy's own contents. Anything else (a stale, truncated,
/// corrupt or foreign file) is ignored and the OBJ is parsed and the copy rewritten:
/// the cache is never trusted, only checked. Copies are written to a temporary file
/// and renamed into place, so a reader never sees half of one.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "core/geometry/mesh.h"
#include "core/util/work_progress.h"

namespace accelviz {

/// Where copies live: $XDG_CACHE_HOME/accelviz, else $HOME/.cache/accelviz; nullopt
/// when neither variable is set.
std::optional<std::filesystem::path> default_mesh_cache_dir();

/// What identifies one version of an OBJ file (see the top of this file).
struct ObjKey {
    std::string path;        ///< absolute, normalised
    uint64_t size = 0;
    int64_t mtime_ns = 0;
    uint64_t edge_hash = 0;  ///< of the first and the last MiB

    bool operator==(const ObjKey&) const = default;
};

/// The key of the file at `path`; nullopt if it cannot be read.
std::optional<ObjKey> obj_key(const std::string& path);

/// Where the copy of the file with this key goes in `cache_dir` (named by a hash of its path).
std::filesystem::path mesh_cache_file(const std::filesystem::path& cache_dir, const ObjKey& key);

/// The mesh in `file` if it is a valid copy made for `key` (mesh.name is key.path's
/// original spelling, `name`); nullopt otherwise, for whatever reason.
std::optional<Mesh> read_mesh_cache(const std::filesystem::path& file, const ObjKey& key, const std::string& name);

/// Writes the copy of `mesh` for `key` to `file` (creating its directory); false if
/// it could not (a read-only disk is no error: the OBJ is simply parsed next time)
/// or was cancelled. `progress` counts a stage "writing the cache copy" (its hash, then
/// its bytes, in pieces of 8 MiB) and may cancel it: nothing is left behind then.
/// Temporary copies that processes no longer running left in the directory (a window
/// closed mid-write) are removed first.
bool write_mesh_cache(const std::filesystem::path& file, const ObjKey& key, const Mesh& mesh,
                      WorkProgress* progress = nullptr);

}  // namespace accelviz
