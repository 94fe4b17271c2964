// The `mbgen` command: one CLI11 subcommand per job, each in its own <name>_command.cpp that
// registers itself with add_<name>_command(app, status). The options that load a robot are parsed
// by description_options.hpp for all of them, and every command exits with the codes of
// exit_codes.hpp.
#include <CLI/CLI.hpp>

#include "cli/exit_codes.hpp"
#include "cli/fit_ssv_command.hpp"
#include "cli/generate_command.hpp"
#include "cli/inspect_command.hpp"
#include "cli/view_command.hpp"

#ifndef MBGEN_VERSION
#define MBGEN_VERSION "unknown"
#endif

int main(int argc, char** argv) {
  CLI::App app{"mbgen: code generator for the multibody dynamics of walking robots"};
  app.set_version_flag("--version", "mbgen " MBGEN_VERSION);
  app.require_subcommand(1);
  int status = 0;
  mbgen::cli::add_inspect_command(app, status);
  mbgen::cli::add_generate_command(app, status);
  mbgen::cli::add_fit_ssv_command(app, status);
  mbgen::cli::add_view_command(app, status);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; a usage error exits kUsage (exit_codes.hpp).
    return app.exit(e) == 0 ? mbgen::cli::kSuccess : mbgen::cli::kUsage;
  }
  return status;
}
