#include "app/cli/scene_input.h"

#include <iostream>

#include "core/geometry/scene.h"

namespace accelviz::cli {

void note_degenerate_triangles(const Mesh& mesh, const std::string& source, const char* command) {
    if (auto note = degenerate_note(mesh)) std::cerr << "accelviz " << command << ": " << source << ": " << *note << "\n";
}

Expected<Mesh> load_scene_noting(const std::string& source, const char* command) {
    Expected<Mesh> mesh = load_scene(source);
    if (mesh) note_degenerate_triangles(*mesh, source, command);
    return mesh;
}

}  // namespace accelviz::cli
