#pragma once
/// Each subcommand registers itself on the top-level CLI::App. The returned
/// function runs it after parsing and gives the process exit code.

#include <functional>

#include <CLI/CLI.hpp>

namespace accelviz::cli {

/// A registered subcommand: the CLI11 node, and what to run when it was chosen
/// (returns the process exit code). `sub` is null for a command not built yet.
struct Command {
    CLI::App* sub = nullptr;
    std::function<int()> run;
};

Command register_render(CLI::App& app);
Command register_trace(CLI::App& app);
Command register_bench(CLI::App& app);
Command register_bench_view(CLI::App& app);
Command register_bench_motion(CLI::App& app);
Command register_query(CLI::App& app);
Command register_export(CLI::App& app);
Command register_check(CLI::App& app);

}  // namespace accelviz::cli
