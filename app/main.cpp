// accelviz: see how ray tracers find what a ray hits, fast.
//
// With no subcommand, `accelviz [SCENE]` opens the window. Subcommands: render
// (images, headless), trace (one ray's events as JSON), bench (speed figures as JSON).
#include <iostream>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/cli/commands.h"
#include "app/gui/window.h"
#include "core/geometry/scene.h"

namespace {

/// The window's default scene: the teapot once it is built in, the cube until then.
std::string default_window_scene() {
    for (const accelviz::BuiltinInfo& info : accelviz::builtin_scenes())
        if (info.name == "teapot") return "builtin:teapot";
    return "builtin:cube";
}

}  // namespace

int main(int argc, char** argv) {
    using namespace accelviz::cli;
    CLI::App app{"accelviz: see how ray tracers find what a ray hits, fast."};
    app.require_subcommand(0, 1);
    std::string scene = default_window_scene();
    app.add_option("SCENE", scene, "Scene for the window: an OBJ path or builtin:NAME (default: " + scene + ")");
    const std::vector<Command> commands = {register_render(app), register_trace(app), register_bench(app)};
    CLI11_PARSE(app, argc, argv);
    try {
        for (const Command& command : commands)
            if (command.sub && command.sub->parsed()) return command.run();
        // No subcommand: the window.
        accelviz::AppState state;
        state.scene = scene;
        return accelviz::run_window(state);
    } catch (const std::exception& e) {
        std::cerr << "accelviz: " << e.what() << "\n";
        return 1;
    }
}
