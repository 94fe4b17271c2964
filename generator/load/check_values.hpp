#pragma once
// Checks on one link's or one joint's values as the parsers read them, before any merging, so
// that a failure names the file, line and element. Each failure is a LoadError with the fix;
// each doubtful-but-usable value is a warning; each value changed on the way (round-off treated
// as zero, an inertia repaired on request) is a note.
#include <string>
#include <vector>

#include "mbgen/spatial/types.hpp"

namespace mbgen::gen {

/// Where the checks report, and what they may change.
struct ValueReport {
  std::vector<std::string>& warnings;
  std::vector<std::string>& notes;
  /// Replace an inertia that no rigid body has (a negative principal moment beyond round-off,
  /// a broken triangle inequality) by the nearest valid one, with a note, instead of refusing
  /// or warning (like MuJoCo's balanceinertia). Off by default: such data is an error to fix.
  bool repair_inertia = false;
};

/// Smallest principal moment (kg m^2) that counts as a value rather than round-off: negative
/// moments and triangle-inequality violations below max(kInertiaRelativeRoundoff * the largest
/// moment, kInertiaAbsoluteRoundoff) are exporter round-off (iCub's head: ixz = 2.4e-35, all
/// else 0), far under any physical link.
inline constexpr double kInertiaRelativeRoundoff = 1e-6;  ///< URDFs print ~6 significant digits
inline constexpr double kInertiaAbsoluteRoundoff = 1e-12;

/// One link's inertia as written (mass, rotational inertia about the centre of mass); returns
/// the rotational inertia to use. Errors: negative or non-finite mass, a negative principal
/// moment beyond round-off (unless report.repair_inertia). Round-off is treated as zero, with a
/// note. A triangle-inequality violation beyond round-off is a warning (real URDFs have them and
/// users need them loaded), or repaired with a note on request.
Mat3<double> check_link_inertia(const std::string& file, int line, const std::string& link, double mass,
                                const Mat3<double>& I_C, ValueReport& report);

/// The nearest rotational inertia (in principal axes) that a rigid body can have: negative
/// principal moments raised to 0, then the triangle inequality restored by the smallest equal
/// shift of the three moments along (1, 1, -1).
Mat3<double> nearest_valid_inertia(const Mat3<double>& I_C);

/// A bounded joint's limits as written: lower above upper is an error.
void check_joint_limits(const std::string& file, int line, const std::string& joint, double lower, double upper);

}  // namespace mbgen::gen
