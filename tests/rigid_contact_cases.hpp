#pragma once
// Contacts for the rigid-contact tests (test_rigid_contact_dynamics.cpp,
// test_rigid_contact_derivatives.cpp) on any tree: a user frame on each leaf body, offset from the
// body's origin and turned (so that the frame's placement is exercised), held as a whole frame
// (6 rows) where the leaf's chain has at least 7 coordinates of its own (not a floating base's,
// not on a chain already held) and as a point (3 rows) where it has at least 3 (a quadruped's
// leg), while the rows stay below nv: J is then block triangular. A contact whose rows would not
// add their number to J's rank at a random configuration (chains whose joints move the point in
// a plane, the delta robot's) is left out: a contact set must have independent rows (the
// Singular status is tested on purpose elsewhere).
#include <Eigen/SVD>
#include <random>
#include <vector>

#include "mbgen/algorithm/rigid_contact_dynamics.hpp"

namespace mbgen::test {

/// The rank of the contacts' Jacobian at a fixed random configuration (relative threshold 1e-9).
inline int jacobian_rank(const Model& model, const std::vector<RigidContact>& contacts) {
  std::mt19937_64 rng(7);
  Data<double> data(model);
  compute_joint_jacobians<double>(model, data, random_configuration<double>(model, rng));
  int m = 0;
  for (const RigidContact& c : contacts) m += c.rows();
  MatX<double> J(m, model.nv());
  Mat6X<double> frame_J(6, model.nv());
  int row = 0;
  for (const RigidContact& c : contacts) {
    const SE3<double>& X = data.X_WF[c.frame];
    detail::point_frame_jacobian<double>(model, data, model.frame(c.frame).body, X.translation, X.rotation,
                                         ReferenceFrame::Local, frame_J);
    J.middleRows(row, c.rows()) = frame_J.topRows(c.rows());
    row += c.rows();
  }
  Eigen::JacobiSVD<MatX<double>> svd(J);
  svd.setThreshold(1e-9);
  return static_cast<int>(svd.rank());
}

/// Adds the contacts' frames to `model` and returns the contacts (possibly none: a chain too short).
inline std::vector<RigidContact> leaf_contacts(Model& model, std::mt19937_64& rng) {
  std::vector<char> has_child(static_cast<std::size_t>(model.num_bodies()), 0);
  for (int k = 1; k < model.num_bodies(); ++k) has_child[static_cast<std::size_t>(model.body(BodyIndex(k)).parent.value())] = 1;
  std::uniform_real_distribution<double> offset(-0.05, 0.05);
  std::vector<RigidContact> contacts;
  std::vector<char> held(static_cast<std::size_t>(model.nv()), 0);
  int rows = 0;
  for (int k = 1; k < model.num_bodies(); ++k) {
    if (has_child[static_cast<std::size_t>(k)]) continue;
    int chain = 0;  // the leaf's own coordinates
    for (BodyIndex j(k); j != kWorldBody; j = model.body(j).parent) {
      const Joint& joint = model.joint(model.body(j).joint);
      if (joint.type == JointType::Floating) continue;
      for (int c = 0; c < joint.nv; ++c) chain += held[static_cast<std::size_t>(joint.idx_v + c)] ? 0 : 1;
    }
    const RigidContactKind kind = chain >= 7 ? RigidContactKind::Frame : RigidContactKind::Point;
    const int r = kind == RigidContactKind::Frame ? 6 : 3;
    if (chain < 3 || rows + r >= model.nv()) continue;
    Frame frame;
    frame.name = "contact_" + std::to_string(k);
    frame.kind = FrameKind::User;
    frame.body = BodyIndex(k);
    frame.X_BF.translation = Vec3<double>(offset(rng), offset(rng), offset(rng));
    frame.X_BF.rotation = Eigen::AngleAxisd(0.3, Vec3<double>(1, 2, 3).normalized()).toRotationMatrix();
    const FrameIndex f = model.add_frame(frame);
    contacts.push_back({f, kind});
    if (jacobian_rank(model, contacts) < rows + r) {
      contacts.pop_back();
      continue;
    }
    for (BodyIndex j(k); j != kWorldBody; j = model.body(j).parent)
      for (int c = 0; c < model.joint(model.body(j).joint).nv; ++c) held[static_cast<std::size_t>(model.joint(model.body(j).joint).idx_v + c)] = 1;
    rows += r;
  }
  return contacts;
}

}  // namespace mbgen::test
