// accelviz: see how ray tracers find what a ray hits, fast.
//
// With no subcommand, `accelviz [SCENE] [--preset FILE] [structure and camera flags]`
// opens the window (on what `render` would draw with the same flags). Subcommands:
// render (images, headless), trace (one ray's events as JSON), bench (speed figures),
// bench-view (the window's frame times), bench-motion (refit against rebuild), query
// (nearest point, inside), export and check (structures in the exchange format).
#include <iostream>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <CLI/CLI.hpp>

#include "app/cli/commands.h"
#include "app/cli/progress.h"
#include "app/cli/window_flags.h"
#include "app/gui/window.h"
#include "core/geometry/scene.h"

namespace {

/// The window's default scene: the teapot once it is built in, the cube until then.
std::string default_window_scene() {
    for (const accelviz::BuiltinInfo& info : accelviz::builtin_scenes())
        if (info.name == "teapot") return "builtin:teapot";
    return "builtin:cube";
}

/// glibc's malloc gives blocks over a threshold (from 128 KiB, raised as big blocks are
/// freed) their own mapping, and hands free memory at the top of its heap back to the
/// system; both thresholds move with what the process has freed so far. A software
/// renderer (llvmpipe) allocates and frees big buffers every frame: depending on that
/// history, every frame then took fresh pages from the system, and a frame of the 3D
/// view took twice as long in one run as in the next (docs/performance.md). Fixed
/// thresholds keep such blocks in the heap, reused from frame to frame. The structures'
/// big arrays have their own mappings (core/util/large_array.h) and are not affected.
void keep_freed_memory_for_reuse() {
#if defined(__GLIBC__)
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
#endif
}

}  // namespace

int main(int argc, char** argv) {
    keep_freed_memory_for_reuse();
    using namespace accelviz::cli;
    CLI::App app{"accelviz: see how ray tracers find what a ray hits, fast."};
    app.require_subcommand(0, 1);
    const std::string default_scene = default_window_scene();
    const auto window = add_window_flags(app, default_scene);
    const std::vector<Command> commands = {register_render(app), register_trace(app), register_bench(app),
                                           register_bench_view(app), register_bench_motion(app), register_query(app),
                                           register_export(app), register_check(app)};
    // The mesh cache (core/geometry/mesh_cache.h), for the window and every command.
    bool no_cache = false;
    const std::string no_cache_help =
        "Parse OBJ files afresh: neither read nor write the binary copies kept in $XDG_CACHE_HOME/accelviz "
        "(else ~/.cache/accelviz) that make a file's second load fast";
    app.add_flag("--no-cache", no_cache, no_cache_help);
    for (const Command& command : commands)
        if (command.sub) command.sub->add_flag("--no-cache", no_cache, no_cache_help);
    // Progress lines on stderr for steps over two seconds (app/cli/progress.h).
    bool quiet = false;
    for (const Command& command : commands)
        if (command.sub)
            command.sub->add_flag("--quiet", quiet, "No progress lines on stderr for loads and builds over 2 s");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help: the help text, exit 0
        // A mistake in the flags: one line, named like the program's other errors, with
        // where to look (CLI11's own report adds a second line and no command name).
        std::string who = "accelviz";
        for (const Command& command : commands)
            if (command.sub && (command.sub->parsed() || (argc > 1 && command.sub->get_name() == argv[1]))) {
                who += " " + command.sub->get_name();
                break;
            }
        std::cerr << who << ": " << e.what() << "; see " << who << " --help\n";
        return e.get_exit_code();
    }
    accelviz::set_default_mesh_cache(no_cache ? accelviz::MeshCache::Skip : accelviz::MeshCache::Use);
    set_progress_lines(!quiet);
    try {
        for (const Command& command : commands)
            if (command.sub && command.sub->parsed()) return command.run();
        // No subcommand: the window.
        auto state = window_state(*window, default_scene);
        if (!state) {
            std::cerr << "accelviz: " << state.error() << "\n";
            return 1;
        }
        const bool first_preset = window->lecture && window->scene.empty() && !window->preset.state;
        return accelviz::run_window(std::move(*state), window->preset.state ? window->preset.path : "", window->lecture,
                                    first_preset);
    } catch (const std::exception& e) {
        std::cerr << "accelviz: " << e.what() << "\n";
        return 1;
    }
}
