// Checks on one link's or one joint's values as written in the description (before merging),
// so that the message can name the element and its line.
#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include <cmath>

#include "load/load_error.hpp"
#include "load/check_values.hpp"

namespace mbgen::gen {

namespace {
/// Relative tolerance on principal moments: URDFs print inertias with ~6 significant digits,
/// so a thin rod (one moment ~0, the other two equal) may come out slightly negative or slightly
/// off the triangle inequality from rounding alone.
constexpr double kInertiaRelativeTolerance = 1e-6;
}  // namespace

void check_link_inertia(const std::string& file, int line, const std::string& link, double mass,
                        const Mat3<double>& I_C, std::vector<std::string>& warnings) {
  const std::string element = fmt::format("link '{}'", link);
  if (!std::isfinite(mass) || mass < 0)
    throw LoadError(file, line, element, fmt::format("negative mass {} kg", mass),
                    "give <mass value=\"...\"/> a value >= 0 (a massless link may have value=\"0\")");
  if (!I_C.allFinite())
    throw LoadError(file, line, element, "inertia has a non-finite entry", "give finite ixx ... izz");
  const Eigen::SelfAdjointEigenSolver<Mat3<double>> eig(I_C, Eigen::EigenvaluesOnly);
  const Vec3<double> m = eig.eigenvalues();  // ascending
  const double tolerance = kInertiaRelativeTolerance * std::abs(I_C.trace());
  if (m[0] < -tolerance)
    throw LoadError(file, line, element,
                    fmt::format("inertia is not positive semi-definite (principal moments {:.6g}, {:.6g}, {:.6g})",
                                m[0], m[1], m[2]),
                    "check the signs of ixx, iyy, izz (>= 0) and that the products ixy, ixz, iyz are not too "
                    "large; recompute the inertia from the link's geometry and mass");
  // Principal moments of a real body satisfy a + b >= c for each ordering; the largest is c.
  if (m[0] + m[1] < m[2] - tolerance)
    warnings.push_back(fmt::format(
        "link '{}' (line {}): inertia breaks the triangle inequality (principal moments {:.6g} + {:.6g} < {:.6g}); "
        "loaded as given, but no rigid body has it and some simulators (MuJoCo) reject it",
        link, line, m[0], m[1], m[2]));
}

void check_joint_limits(const std::string& file, int line, const std::string& joint, double lower, double upper) {
  if (lower > upper)
    throw LoadError(file, line, fmt::format("joint '{}'", joint),
                    fmt::format("lower limit {} is above upper limit {}", lower, upper),
                    "swap the lower and upper attributes of <limit>");
}

}  // namespace mbgen::gen
