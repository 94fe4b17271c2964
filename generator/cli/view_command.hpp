#pragma once
// `mbgen view DESCRIPTION [--extras FILE] [--trajectory FILE.csv] --out FILE.html [--near M] [--fps N]
// [--fit] [--no-meshes]`: one self-contained HTML page showing the robot (its SSVs, meshes, loop
// closures, near pairs) at its assembled pose or along a trajectory (generator/view/). Exits with
// the codes of exit_codes.hpp.
#include <CLI/CLI.hpp>

namespace mbgen::cli {

void add_view_command(CLI::App& app, int& status);

}  // namespace mbgen::cli
