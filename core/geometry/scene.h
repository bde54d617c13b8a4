#pragma once
/// Where meshes come from: an OBJ file path, or a built-in scene "builtin:NAME?k=v&k=v".

#include <string>
#include <vector>

#include "core/geometry/mesh.h"
#include "core/util/expected.h"

namespace accelviz {

/// Loads an OBJ file through tinyobjloader; polygons are fan-triangulated.
/// Errors (one line) name the file and, where known, the line: missing,
/// unreadable, empty (no triangles), malformed (bad numbers, indices out of range).
Expected<Mesh> load_obj(const std::string& path);

/// A built-in scene, e.g. "cube", "cornell", "teapot?n=8", "soup?n=1000&seed=7".
/// `spec` is what follows "builtin:". Unknown names or parameters are errors.
Expected<Mesh> make_builtin(const std::string& spec);

/// The names make_builtin accepts, each with a one-line description and its parameters.
struct BuiltinInfo {
    std::string name;
    std::string description;
};
const std::vector<BuiltinInfo>& builtin_scenes();

/// "builtin:..." → make_builtin, anything else → load_obj.
Expected<Mesh> load_scene(const std::string& source);

}  // namespace accelviz
