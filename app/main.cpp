// accelviz: see how ray tracers find what a ray hits, fast.
//
// One executable with subcommands: render (images, headless), trace (one ray's
// events as JSON), bench (speed figures as JSON).
#include <iostream>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/cli/commands.h"

int main(int argc, char** argv) {
    using namespace accelviz::cli;
    CLI::App app{"accelviz: see how ray tracers find what a ray hits, fast."};
    app.require_subcommand(0, 1);
    const std::vector<Command> commands = {register_render(app), register_trace(app), register_bench(app)};
    CLI11_PARSE(app, argc, argv);
    try {
        for (const Command& command : commands)
            if (command.sub && command.sub->parsed()) return command.run();
    } catch (const std::exception& e) {
        std::cerr << "accelviz: " << e.what() << "\n";
        return 1;
    }
    std::cout << app.help();
    return 0;
}
