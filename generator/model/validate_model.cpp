// Whole-description checks that need the assembled tree: moving joints exist, each moves some
// mass or inertia, closures join two different bodies.
#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "load/load_error.hpp"
#include "model/validate.hpp"
#include "mbgen/joint.hpp"

namespace mbgen::gen {

namespace {

/// S^T Ic S below this (kg m^2 for a rotation, kg for a translation) counts as zero: the joint's
/// row of the mass matrix would vanish at q = 0.
constexpr double kSingularTolerance = 1e-12;

void check_has_moving_joint(const Description& d) {
  if (d.model.nv() > 0) return;
  throw LoadError(d.description_file, 0, fmt::format("robot '{}'", d.model.name), "has no moving joint",
                  "add a revolute, continuous or prismatic joint, or load it with a floating base "
                  "(`base: floating` in the extras, or --floating)");
}

/// Composite inertia of each body's subtree at q = 0, in the body's frame, children first
/// (bodies are numbered parent first, so a reverse sweep visits children before parents).
std::vector<Mat6<double>> composite_inertias_at_zero(const Model& model) {
  std::vector<Mat6<double>> Ic(model.num_bodies());
  for (int b = 0; b < model.num_bodies(); ++b) Ic[b] = model.body(BodyIndex(b)).inertia.matrix();
  for (int b = model.num_bodies() - 1; b > 0; --b) {
    const Joint& joint = model.joint(Model::joint_of(BodyIndex(b)));
    // At q = 0 (identity quaternion for a floating joint) the child frame is the joint frame.
    Ic[joint.parent.value()] += transform_spatial_inertia(joint.X_PJ, Ic[b]);
  }
  return Ic;
}

void check_joints_move_mass(const Description& d) {
  const Model& model = d.model;
  const std::vector<Mat6<double>> Ic = composite_inertias_at_zero(model);
  for (int b = 1; b < model.num_bodies(); ++b) {
    const Joint& joint = model.joint(Model::joint_of(BodyIndex(b)));
    Eigen::MatrixXd S(6, joint.nv);
    for (int k = 0; k < joint.nv; ++k) S.col(k) = joint_subspace_column<double>(joint, k).vector();
    Eigen::MatrixXd M_jj = S.transpose() * Ic[b] * S;
    // A drive's reflected inertia regularises the joint's row of M (rotor.hpp): armature on the
    // diagonal, or a rotor body spinning N times faster.
    if (joint.nv == 1) M_jj(0, 0) += joint.armature + joint.rotor_gear_ratio * joint.rotor_gear_ratio * joint.rotor_inertia;
    const double smallest = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M_jj, Eigen::EigenvaluesOnly).eigenvalues()[0];
    if (smallest > kSingularTolerance) continue;
    throw LoadError(d.description_file, d.urdf_lines.line_of_joint(joint.name), fmt::format("joint '{}'", joint.name),
                    fmt::format("moves no mass or inertia (body '{}' and the bodies below it have none along the "
                                "joint's motion at q = 0): the mass matrix would be singular",
                                model.body(BodyIndex(b)).name),
        fmt::format("give the child link (or a link below it) an <inertial> with non-zero mass and inertia; or give "
                    "the joint a drive whose rotor inertia regularises M (extras: `drives: [{{joint: {}, gear_ratio: "
                    "1, rotor_inertia: 1e-6}}]`); or make the joint fixed",
                    joint.name));
  }
}

void check_closures(const Description& d) {
  for (const ClosureSpec& c : d.closures) {
    const std::string element = fmt::format("closure '{}'", c.name);
    if (c.frame_a == c.frame_b)
      throw LoadError(d.extras_file, c.source_line, element, fmt::format("names '{}' twice", c.frame_a),
                      "a closure joins two different bodies: name one frame on each side of the loop");
    if (!c.resolved_a.valid() || !c.resolved_b.valid()) continue;
    const BodyIndex a = d.model.frame(c.resolved_a).body, b = d.model.frame(c.resolved_b).body;
    if (a == b)
      throw LoadError(d.extras_file, c.source_line, element,
                      fmt::format("'{}' and '{}' are fixed in the same body '{}' (welded by fixed joints), so the "
                                  "closure joins one body to itself",
                                  c.frame_a, c.frame_b, d.model.body(a).name),
                      "a closure joins two different bodies: name one frame on each side of the loop");
  }
}

}  // namespace

void validate_description(const Description& d) {
  check_has_moving_joint(d);
  check_joints_move_mass(d);
  check_closures(d);
}

}  // namespace mbgen::gen
