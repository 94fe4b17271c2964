#pragma once
// Checks on one link's or one joint's values as the parsers read them, before any merging, so
// that a failure names the file, line and element. Each failure is a LoadError with the fix;
// each doubtful-but-usable value is a warning appended to `warnings`.
#include <string>
#include <vector>

#include "mbgen/spatial/types.hpp"

namespace mbgen::gen {

/// One link's inertia as written (mass, rotational inertia about the centre of mass). Errors:
/// negative or non-finite mass, inertia not positive semi-definite. Warning: principal moments
/// that break the triangle inequality (real URDFs have them; users need them loaded).
void check_link_inertia(const std::string& file, int line, const std::string& link, double mass,
                        const Mat3<double>& I_C, std::vector<std::string>& warnings);

/// A bounded joint's limits as written: lower above upper is an error.
void check_joint_limits(const std::string& file, int line, const std::string& joint, double lower, double upper);

}  // namespace mbgen::gen
