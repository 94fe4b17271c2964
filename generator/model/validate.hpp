#pragma once
// Validation of a whole description: what the parsers accept but dynamics cannot use. Each
// failure is a LoadError naming the file, element, problem and fix. (Checks on single values as
// they are read, inertias and limits, are the loaders': load/check_values.hpp.)
#include <string>
#include <vector>

#include "load/description.hpp"

namespace mbgen::gen {

/// Whole-description checks, after the tree and the extras are loaded: at least one moving joint;
/// every joint moves some mass or inertia (else the mass matrix is singular); no closure names
/// one body twice.
void validate_description(const Description& description);

}  // namespace mbgen::gen
