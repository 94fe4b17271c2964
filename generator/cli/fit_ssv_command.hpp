#pragma once
// `mbgen fit-ssv DESCRIPTION [--extras FILE] [--budget N] [--package-path NAME=DIR]... --out FILE.yaml
// [--picture-data DIR]`: fits SSV compounds to each link's meshes (load/fit_link_ssvs.hpp) and
// writes them as the `ssv:` section of an extras file, with a report per link. Exit 0 on success,
// 2 on a bad description, a bad option, or an --out file that mbgen did not write.
#include <CLI/CLI.hpp>

namespace mbgen::cli {

void add_fit_ssv_command(CLI::App& app, int& status);

}  // namespace mbgen::cli
