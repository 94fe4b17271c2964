#pragma once
// The front end's entry point: a description file (and extras) to a Description ready for the
// collision scene and code generation.
#include <string>

#include "load/description.hpp"

namespace mbgen::gen {

/// Loads a URDF or, for a .xml file, an MJCF (and extras): read_description (load/), then
/// validate_description and build_topology (this stage). Throws LoadError with file, line,
/// element and fix on bad input.
Description load_description(const std::string& path, const LoadOptions& options = {});

}  // namespace mbgen::gen
