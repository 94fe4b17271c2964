// Checks on one link's or one joint's values as written in the description (before merging),
// so that the message can name the element and its line.
#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "load/check_values.hpp"
#include "load/load_error.hpp"

namespace mbgen::gen {

namespace {

Mat3<double> from_principal(const Eigen::SelfAdjointEigenSolver<Mat3<double>>& eig, const Vec3<double>& moments) {
  const Mat3<double>& V = eig.eigenvectors();
  Mat3<double> I = V * moments.asDiagonal() * V.transpose();
  return (I + I.transpose()) / 2;
}

}  // namespace

Mat3<double> nearest_valid_inertia(const Mat3<double>& I_C) {
  const Eigen::SelfAdjointEigenSolver<Mat3<double>> eig(I_C);
  Vec3<double> m = eig.eigenvalues().cwiseMax(0.0);  // ascending before the clamp, and after it
  const double excess = m[0] + m[1] - m[2];
  if (excess < 0) {  // project onto the plane m0 + m1 = m2: t = excess / 3 along (1, 1, -1)
    const double t = excess / 3;
    m += Vec3<double>(-t, -t, t);
  }
  return from_principal(eig, m);
}

Mat3<double> check_link_inertia(const std::string& file, int line, const std::string& link, double mass,
                                const Mat3<double>& I_C, ValueReport& report) {
  const std::string element = fmt::format("link '{}'", link);
  if (!std::isfinite(mass) || mass < 0)
    throw LoadError(file, line, element, fmt::format("negative mass {} kg", mass),
                    "give <mass value=\"...\"/> a value >= 0 (a massless link may have value=\"0\")");
  if (!I_C.allFinite())
    throw LoadError(file, line, element, "inertia has a non-finite entry", "give finite ixx ... izz");
  const Eigen::SelfAdjointEigenSolver<Mat3<double>> eig(I_C);
  const Vec3<double> m = eig.eigenvalues();  // ascending
  const double roundoff = std::max(kInertiaRelativeRoundoff * m.cwiseAbs().maxCoeff(), kInertiaAbsoluteRoundoff);
  const std::string moments = fmt::format("principal moments {:.6g}, {:.6g}, {:.6g} kg m^2", m[0], m[1], m[2]);
  const bool negative = m[0] < -roundoff;
  // Principal moments of a real body satisfy a + b >= c for each ordering; the largest is c.
  const bool triangle = m[0] + m[1] < m[2] - roundoff;
  if ((negative || triangle) && report.repair_inertia) {
    const Mat3<double> repaired = nearest_valid_inertia(I_C);
    const Eigen::SelfAdjointEigenSolver<Mat3<double>> after(repaired, Eigen::EigenvaluesOnly);
    report.notes.push_back(fmt::format(
        "link '{}' (line {}): inertia repaired (--repair-inertia): {} -> {:.6g}, {:.6g}, {:.6g} (change {:.3g} kg m^2)",
        link, line, moments, after.eigenvalues()[0], after.eigenvalues()[1], after.eigenvalues()[2],
        (repaired - I_C).norm()));
    return repaired;
  }
  if (negative)
    throw LoadError(file, line, element, fmt::format("inertia is not positive semi-definite ({})", moments),
                    "check the signs of ixx, iyy, izz (>= 0) and that the products ixy, ixz, iyz are not too "
                    "large; recompute the inertia from the link's geometry and mass, or load it with "
                    "--repair-inertia (the nearest valid inertia, the change printed)");
  if (triangle)
    report.warnings.push_back(fmt::format(
        "link '{}' (line {}): inertia breaks the triangle inequality ({}: {:.6g} + {:.6g} < {:.6g}); "
        "loaded as given, but no rigid body has it and some simulators (MuJoCo) reject it (--repair-inertia "
        "replaces it by the nearest valid one)",
        link, line, moments, m[0], m[1], m[2]));
  if (m[0] < 0) {  // round-off below zero: zero
    report.notes.push_back(fmt::format("link '{}' (line {}): principal moment {:.3g} kg m^2 is round-off (below {:.3g}): "
                                       "treated as 0",
                                       link, line, m[0], roundoff));
    return from_principal(eig, m.cwiseMax(0.0));
  }
  return I_C;
}

void check_joint_limits(const std::string& file, int line, const std::string& joint, double lower, double upper) {
  if (lower > upper)
    throw LoadError(file, line, fmt::format("joint '{}'", joint),
                    fmt::format("lower limit {} is above upper limit {}", lower, upper),
                    "swap the lower and upper attributes of <limit>");
}

}  // namespace mbgen::gen
