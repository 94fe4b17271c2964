#pragma once
// `--package-path NAME=DIR`, shared by the commands that read meshes (fit-ssv, and inspect and
// generate for `scene: collision: fit`): checked when the command line is parsed, so a malformed
// value is a usage error (exit 2) naming it.
#include <CLI/CLI.hpp>

#include <stdexcept>
#include <string>
#include <vector>

#include "mesh/mesh_path.hpp"

namespace mbgen::cli {

inline void add_package_path_option(CLI::App* command, std::vector<std::string>& values, const std::string& purpose) {
  command
      ->add_option("--package-path", values,
                   "NAME=DIR: package://NAME/x is DIR/x (repeatable; ROS_PACKAGE_PATH is searched after these), " + purpose)
      ->check([](const std::string& value) -> std::string {
        try {
          mesh::parse_package_path(value);
          return "";
        } catch (const std::invalid_argument& e) {
          return e.what();
        }
      });
}

}  // namespace mbgen::cli
