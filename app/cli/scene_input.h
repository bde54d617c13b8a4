#pragma once
/// Loading a command's scene: load_scene, and a word on stderr about triangles
/// no ray can hit (zero area), so that a picture with holes is not a mystery.

#include <optional>
#include <string>

#include "core/accel/accelerator.h"
#include "core/geometry/mesh.h"
#include "core/util/expected.h"

namespace accelviz::cli {

/// load_scene(source); when some triangles have zero area, says how many on stderr
/// as "accelviz COMMAND: SOURCE: k of N triangles have zero area ...".
Expected<Mesh> load_scene_noting(const std::string& source, const char* command);

/// Prints a scene's note (degenerate_note, already computed) the same way; none: nothing.
void print_scene_note(const std::optional<std::string>& note, const std::string& source, const char* command);

/// When the memory budget capped the build (core/accel/memory_budget.h), says so on
/// stderr as "accelviz COMMAND: memory budget ...": the structure is not the one the
/// flags alone would give.
void print_memory_budget_note(const Accelerator& accel, const char* command);

}  // namespace accelviz::cli
