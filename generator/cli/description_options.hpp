#pragma once
// The options every command that loads a robot shares, parsed one way for all: the description
// (URDF or MJCF), --extras, --floating/--fixed, --repair-inertia, --mimic and --package-path. Checked when
// the command line is parsed, so a malformed value is a usage error (exit 2) naming it.
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "model/load_description.hpp"

namespace mbgen::cli {

struct DescriptionOptions {
  std::string description;                 ///< URDF or MJCF (.xml) file
  std::string extras;                      ///< YAML extras; empty: robot.yaml beside the description, if any
  bool floating = false, fixed = false;    ///< override the extras' base
  bool repair_inertia = false;             ///< nearest valid inertias instead of refusing
  std::vector<std::string> package_paths;  ///< NAME=DIR: where package://NAME/ meshes are
  std::string mimic;                       ///< couple | independent: overrides the extras' `mimic`

  /// What gen::load_description reads; throws std::invalid_argument on a malformed package path
  /// (the parse-time check makes that a usage error first).
  gen::LoadOptions load_options() const;
};

/// What the command uses the options for, in their help.
struct DescriptionHelp {
  std::string extras = "YAML extras (default: robot.yaml beside the description, if any)";
  std::string package_path = "for the meshes `scene: collision: fit` reads";
};

/// Adds the positional DESCRIPTION and the shared options to `command`.
void add_description_options(CLI::App* command, DescriptionOptions& options, const DescriptionHelp& help = {});

}  // namespace mbgen::cli
