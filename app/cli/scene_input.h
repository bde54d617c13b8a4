#pragma once
/// Loading a command's scene: load_scene, and a word on stderr about triangles
/// no ray can hit (zero area), so that a picture with holes is not a mystery.

#include <optional>
#include <string>

#include "core/geometry/mesh.h"
#include "core/util/expected.h"

namespace accelviz::cli {

/// load_scene(source); when some triangles have zero area, says how many on stderr
/// as "accelviz COMMAND: SOURCE: k of N triangles have zero area ...".
Expected<Mesh> load_scene_noting(const std::string& source, const char* command);

/// Prints a scene's note (degenerate_note, already computed) the same way; none: nothing.
void print_scene_note(const std::optional<std::string>& note, const std::string& source, const char* command);

}  // namespace accelviz::cli
