#pragma once
// `mbgen generate DESCRIPTION [--extras FILE] --out DIR [--name NAME] [--scalar double|float|both]
// [--floating|--fixed] [--frames a,b,...]`: emits the robot's unrolled, allocation-free C++.
// Exit status 0 on success, 2 on bad input or a refused write (the reason goes to stderr).
#include <CLI/CLI.hpp>

namespace mbgen::cli {

/// Registers the `generate` subcommand on `app`; when it runs, its exit status goes to `status`.
void add_generate_command(CLI::App& app, int& status);

}  // namespace mbgen::cli
