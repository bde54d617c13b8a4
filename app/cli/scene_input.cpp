#include "app/cli/scene_input.h"

#include <iostream>

#include "app/cli/progress.h"
#include "core/geometry/scene.h"

namespace accelviz::cli {

void print_scene_note(const std::optional<std::string>& note, const std::string& source, const char* command) {
    if (note) std::cerr << "accelviz " << command << ": " << source << ": " << *note << "\n";
}

Expected<Mesh> load_scene_noting(const std::string& source, const char* command) {
    Expected<Mesh> mesh = [&] {
        const StepProgress progress(command, "loading " + source);
        return load_scene(source);
    }();
    if (mesh) print_scene_note(degenerate_note(*mesh), source, command);
    return mesh;
}

void print_memory_budget_note(const Accelerator& accel, const char* command) {
    const nlohmann::json stats = accel.stats();
    if (!stats.contains("notes")) return;
    for (const auto& note : stats["notes"])
        if (note.is_string() && note.get<std::string>().rfind("memory budget", 0) == 0)
            std::cerr << "accelviz " << command << ": " << note.get<std::string>() << "\n";
}

}  // namespace accelviz::cli
