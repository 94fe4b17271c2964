#pragma once
// `mbgen inspect DESCRIPTION [--extras FILE] [--floating|--fixed] [--json]`: loads a robot
// description and reports what mbgen understood (tree, DoF, mass, frames, closures as given,
// actuated joints, drives, warnings) with a verdict. Exit status 0 when it loads, 2 on a
// LoadError (its text goes to stderr).
#include <CLI/CLI.hpp>

namespace mbgen::cli {

/// Registers the `inspect` subcommand on `app`; when it runs, its exit status goes to `status`.
void add_inspect_command(CLI::App& app, int& status);

}  // namespace mbgen::cli
