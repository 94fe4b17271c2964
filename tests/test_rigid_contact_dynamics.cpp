// Forward dynamics with rigid contacts held (runtime/include/mbgen/algorithm/
// rigid_contact_dynamics.hpp) against what it must satisfy, computed independently:
//  - the contacts' accelerations at the result vanish: the frames' world velocities (the
//    kinematics' body velocities) pushed through dual numbers along the motion (q (+) eps v,
//    v + eps a) give their time derivatives exactly; 1e-10 relative to the free accelerations';
//  - the equations of motion M a + h = tau + J^T lambda with M from crba, h from rnea and J from the
//    kinematics' frame velocities at unit joint velocities: 1e-10 relative;
//  - a and lambda equal a dense LU solve of the KKT system built from those independent J and
//    gamma: 1e-10 (relative, lambda scaled by its largest entry);
// on every URDF of the suite with fixed and floating base (contacts on the leaves,
// rigid_contact_cases.hpp); dependent contacts report Singular and NaN states NotFinite, a model with loops
// and a frame that is not the model's are refused, and the call allocates nothing.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <random>

#include "autodiff_reference.hpp"
#include "malloc_guard.hpp"
#include "mbgen/algorithm/rigid_contact_dynamics.hpp"
#include "rigid_contact_cases.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

/// The contacts' rows (classical acceleration of each frame's origin and its angular acceleration,
/// in the frame's axes) along the motion through (q, v) with accelerations a: d/dt of the world
/// velocities, exact by one dual pass, rotated into the frame.
VecX<double> contact_rows(const Model& model, const RigidContactWorkspace<double>& ws, const VecX<double>& q,
                          const VecX<double>& v, const VecX<double>& a) {
  Data<Dual> data(model);
  const VecX<Dual> qd = seeded_configuration_along(model, q, v);
  VecX<Dual> vd = seeded_vector(v);
  for (int k = 0; k < v.size(); ++k) vd[k].derivatives()[0] = a[k];
  forward_kinematics<Dual>(model, data, qd, vd);
  VecX<double> rows(ws.m);
  for (std::size_t k = 0; k < ws.contacts.size(); ++k) {
    const Frame& frame = model.frame(ws.contacts[k].frame);
    const SE3<Dual> X_WF = data.X_WB[frame.body] * frame.X_BF.cast<Dual>();
    const Motion<Dual> v_F = frame.X_BF.cast<Dual>().act_inv(data.v[frame.body]);
    const Vec3<Dual> linear = X_WF.rotation * v_F.linear, angular = X_WF.rotation * v_F.angular;
    Mat3<double> R;
    Vec3<double> dlinear, dangular;
    for (int r = 0; r < 3; ++r) {
      dlinear[r] = linear[r].derivatives()[0];
      dangular[r] = angular[r].derivatives()[0];
      for (int c = 0; c < 3; ++c) R(r, c) = X_WF.rotation(r, c).value();
    }
    rows.segment<3>(ws.first_row[k]) = R.transpose() * dlinear;
    if (ws.contacts[k].rows() == 6) rows.segment<3>(ws.first_row[k] + 3) = R.transpose() * dangular;
  }
  return rows;
}

/// The contacts' Jacobian from their velocities at unit joint velocities (the frames' own axes).
MatX<double> contact_jacobian(const Model& model, const RigidContactWorkspace<double>& ws, const VecX<double>& q) {
  Data<double> data(model);
  MatX<double> J(ws.m, model.nv());
  for (int c = 0; c < model.nv(); ++c) {
    forward_kinematics<double>(model, data, q, VecX<double>::Unit(model.nv(), c));
    for (std::size_t k = 0; k < ws.contacts.size(); ++k) {
      const Frame& frame = model.frame(ws.contacts[k].frame);
      const Motion<double> v_F = frame.X_BF.act_inv(data.v[frame.body]);
      J.col(c).segment<3>(ws.first_row[k]) = v_F.linear;
      if (ws.contacts[k].rows() == 6) J.col(c).segment<3>(ws.first_row[k] + 3) = v_F.angular;
    }
  }
  return J;
}

class RigidContactDynamicsTest : public ::testing::TestWithParam<UrdfCase> {};

TEST_P(RigidContactDynamicsTest, SatisfiesTheContactsAndTheEquationsOfMotion) {
  std::mt19937_64 rng(61);
  Model model = load_tree(GetParam().path, GetParam().base);
  const std::vector<RigidContact> contacts = leaf_contacts(model, rng);
  if (contacts.empty()) GTEST_SKIP() << "no leaf with a chain of 3 or more coordinates";
  Data<double> data(model), other(model);
  RigidContactWorkspace<double> ws(model, contacts);
  const int nv = model.nv(), m = ws.m;
  for (int trial = 0; trial < 3; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    const VecX<double> v = random_vector<double>(nv, rng, 2.0);
    const VecX<double> tau = random_vector<double>(nv, rng, 10.0);
    rigid_contact_dynamics<double>(model, data, ws, q, v, tau);
    ASSERT_EQ(ws.status, RigidContactStatus::Solved);
    const VecX<double> a = ws.a, lambda = ws.lambda;

    const VecX<double> free_a = aba<double>(model, other, q, v, tau);
    const double scale = std::max(1.0, contact_rows(model, ws, q, v, free_a).cwiseAbs().maxCoeff());
    EXPECT_LT(contact_rows(model, ws, q, v, a).cwiseAbs().maxCoeff() / scale, 1e-10) << "trial " << trial;

    const MatX<double> M = crba<double>(model, other, q);
    const VecX<double> h = nonlinear_effects<double>(model, other, q, v);
    const MatX<double> J = contact_jacobian(model, ws, q);
    const VecX<double> residual = M * a + h - tau - J.transpose() * lambda;
    const double force_scale = std::max({tau.cwiseAbs().maxCoeff(), h.cwiseAbs().maxCoeff(), (M * a).cwiseAbs().maxCoeff()});
    EXPECT_LT(residual.cwiseAbs().maxCoeff() / force_scale, 1e-10) << "trial " << trial;

    // The dense KKT system from the independent J and gamma (the rows at a = 0).
    MatX<double> K = MatX<double>::Zero(nv + m, nv + m);
    K.topLeftCorner(nv, nv) = M;
    K.topRightCorner(nv, m) = -J.transpose();
    K.bottomLeftCorner(m, nv) = J;
    VecX<double> rhs(nv + m);
    rhs << tau - h, -contact_rows(model, ws, q, v, VecX<double>::Zero(nv));
    const VecX<double> x = K.partialPivLu().solve(rhs);
    EXPECT_LT(relative_error(a, x.head(nv)), 1e-10) << "trial " << trial;
    EXPECT_LT((lambda - x.tail(m)).cwiseAbs().maxCoeff() / x.tail(m).cwiseAbs().maxCoeff(), 1e-10) << "trial " << trial;
  }
}

TEST_P(RigidContactDynamicsTest, AllocatesNothing) {
  std::mt19937_64 rng(62);
  Model model = load_tree(GetParam().path, GetParam().base);
  const std::vector<RigidContact> contacts = leaf_contacts(model, rng);
  if (contacts.empty()) GTEST_SKIP() << "no leaf with a chain of 3 or more coordinates";
  Data<double> data(model);
  RigidContactWorkspace<double> ws(model, contacts);
  const VecX<double> q = random_configuration<double>(model, rng);
  const VecX<double> v = random_vector<double>(model.nv(), rng), tau = random_vector<double>(model.nv(), rng);
  MallocGuard guard;
  rigid_contact_dynamics<double>(model, data, ws, q, v, tau);
  EXPECT_EQ(guard.count(), 0u);
}

INSTANTIATE_TEST_SUITE_P(AllUrdfs, RigidContactDynamicsTest, ::testing::ValuesIn(all_urdf_cases()), urdf_case_name);

Model iiwa_with_tool_frame(FrameIndex& tool) {
  Model model = load_tree(shared_robot("iiwa14/iiwa14_primitive_collision.urdf"), gen::BaseType::Fixed);
  Frame frame;
  frame.name = "tool";
  frame.kind = FrameKind::User;
  frame.body = BodyIndex(model.num_bodies() - 1);
  frame.X_BF.translation = Vec3<double>(0, 0, 0.1);
  tool = model.add_frame(frame);
  return model;
}

// The same point held twice, or a point of a frame already held: J M^-1 J^T is singular. A NaN in
// the state: NotFinite. Neither returns forces as if they were meaningful.
TEST(RigidContactDynamics, DependentContactsAndNanStatesAreSingular) {
  FrameIndex tool;
  const Model model = iiwa_with_tool_frame(tool);
  Data<double> data(model);
  std::mt19937_64 rng(63);
  const VecX<double> q = random_configuration<double>(model, rng), v = random_vector<double>(7, rng),
                     tau = random_vector<double>(7, rng);
  RigidContactWorkspace<double> one(model, {{tool, RigidContactKind::Point}});
  rigid_contact_dynamics<double>(model, data, one, q, v, tau);
  EXPECT_EQ(one.status, RigidContactStatus::Solved);
  RigidContactWorkspace<double> twice(model, {{tool, RigidContactKind::Point}, {tool, RigidContactKind::Point}});
  rigid_contact_dynamics<double>(model, data, twice, q, v, tau);
  EXPECT_EQ(twice.status, RigidContactStatus::Singular);
  RigidContactWorkspace<double> nested(model, {{tool, RigidContactKind::Frame}, {tool, RigidContactKind::Point}});
  rigid_contact_dynamics<double>(model, data, nested, q, v, tau);
  EXPECT_EQ(nested.status, RigidContactStatus::Singular);
  VecX<double> bad = v;
  bad[3] = std::numeric_limits<double>::quiet_NaN();
  rigid_contact_dynamics<double>(model, data, one, q, bad, tau);
  EXPECT_EQ(one.status, RigidContactStatus::NotFinite);
  rigid_contact_dynamics<double>(model, data, one, q, v, tau);
  EXPECT_EQ(one.status, RigidContactStatus::Solved);  // and back
  EXPECT_STREQ(to_string(RigidContactStatus::Singular), "singular");
  EXPECT_STREQ(to_string(RigidContactStatus::NotFinite), "not_finite");
}

TEST(RigidContactDynamics, RefusesLoopsAndForeignFrames) {
  const gen::Description four_bar = load_loop_case({"four_bar", MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.urdf",
                                                    MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.yaml"});
  try {
    RigidContactWorkspace<double> ws(four_bar.model, {{FrameIndex(1), RigidContactKind::Point}});
    FAIL() << "a model with loops was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("loop closure"), std::string::npos) << e.what();
  }
  FrameIndex tool;
  const Model model = iiwa_with_tool_frame(tool);
  try {
    RigidContactWorkspace<double> ws(model, {{FrameIndex(model.num_frames()), RigidContactKind::Point}});
    FAIL() << "a frame index past the model's was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("is not a frame"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mbgen::test
