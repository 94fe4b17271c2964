#pragma once
// Validation of a description: what the parsers accept but dynamics cannot use. Each failure is
// a LoadError naming the file, line, element, problem and fix; each doubtful-but-usable input is
// a warning appended to the description.
#include <string>
#include <vector>

#include "mbgen/gen/description.hpp"

namespace mbgen::gen {

/// One link's inertia as written (mass, rotational inertia about the centre of mass). Errors:
/// negative or non-finite mass, inertia not positive semi-definite. Warning: principal moments
/// that break the triangle inequality (real URDFs have them; users need them loaded).
void check_link_inertia(const std::string& file, int line, const std::string& link, double mass,
                        const Mat3<double>& I_C, std::vector<std::string>& warnings);

/// A bounded joint's limits as written: lower above upper is an error.
void check_joint_limits(const std::string& file, int line, const std::string& joint, double lower, double upper);

/// Whole-description checks, after the tree and the extras are loaded: at least one moving joint;
/// every joint moves some mass or inertia (else the mass matrix is singular); no closure names
/// one body twice.
void validate_description(const Description& description);

}  // namespace mbgen::gen
