// ABA against CRBA and RNEA (three independent algorithms) on every URDF, fixed and floating base:
//   ABA(q, v, tau) = M(q)^-1 (tau - RNEA(q, v, 0))   and   RNEA(q, v, ABA(q, v, tau)) = tau.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "test_support.hpp"

namespace mbgen::test {
namespace {

class AbaTest : public ::testing::TestWithParam<UrdfCase> {};

TEST_P(AbaTest, MatchesCrbaAndRnea) {
  const Model model = load_tree(GetParam().path, GetParam().base);
  Data<double> data(model);
  std::mt19937_64 rng(42);
  // 1e-10 relative: three O(n) / O(n^2) algorithms that share no code path beyond kinematics.
  constexpr double kTol = 1e-10;
  double worst_solve = 0, worst_roundtrip = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    const VecX<double> v = random_vector<double>(model.nv(), rng, 2.0);
    const VecX<double> tau = random_vector<double>(model.nv(), rng, 10.0);
    const VecX<double> ddq = aba<double>(model, data, q, v, tau);
    const VecX<double> bias = nonlinear_effects<double>(model, data, q, v);
    const MatX<double> M = crba<double>(model, data, q);
    ASSERT_LT(relative_error(M, MatX<double>(M.transpose())), 1e-14);
    const VecX<double> ddq_crba = M.ldlt().solve(tau - bias);
    const VecX<double> tau_back = rnea<double>(model, data, q, v, ddq);
    // Normwise backward errors: the residual of M ddq = tau - bias relative to the size of its
    // terms. They do not grow with the conditioning of M (the 5-bar's 654 t ball makes M
    // badly conditioned, so forward errors in ddq would measure the model, not the algorithm).
    const double scale = M.norm() * ddq.norm() + tau.norm() + bias.norm();
    worst_solve = std::max(worst_solve, (M * (ddq - ddq_crba)).norm() / scale);
    worst_roundtrip = std::max(worst_roundtrip, (tau_back - tau).norm() / scale);
  }
  EXPECT_LT(worst_solve, kTol);
  EXPECT_LT(worst_roundtrip, kTol);
}

INSTANTIATE_TEST_SUITE_P(AllUrdfs, AbaTest, ::testing::ValuesIn(all_urdf_cases()), urdf_case_name);

/// Three links on revolute joints about z, the second and third joint frames at their parent's
/// origin (X_PJ the identity), the second joint with the given armature.
Model z_chain(double armature) {
  Model model;
  BodyIndex parent = kWorldBody;
  for (int j = 0; j < 3; ++j) {
    Joint joint;
    joint.name = "j" + std::to_string(j + 1);
    joint.axis = Vec3<double>::UnitZ();
    if (j == 1) joint.armature = armature;
    if (j == 2) joint.X_PJ = SE3<double>{Mat3<double>::Identity(), Vec3<double>(0.3, 0.1, -0.2)};
    Inertia<double> link;
    link.mass = 1.0 + 0.7 * j;
    link.com = Vec3<double>(0.11 + 0.05 * j, -0.07, 0.03 * j - 0.2);
    link.inertia_com << 0.031, 0.002, -0.004, 0.002, 0.027, 0.003, -0.004, 0.003, 0.019;
    parent = model.add_body(parent, joint, "link" + std::to_string(j + 1), link);
  }
  return model;
}

// ABA's projected inertia Ia = IA - U U^T / D of a 1-DoF joint annihilates its motion subspace
// (Ia S = U - U D^-1 S^T U = 0 when D = S^T U). For a coordinate axis that is a row and a column
// of exact zeros, which aba sets rather than leaves to rounding; rotated about that same axis
// they stay zero, so the parent's articulated inertia keeps its own rigid inertia's column there,
// bit for bit. With an armature on the diagonal, D > S^T U and the column is Ia S = U a / D.
TEST(AbaProjectedInertia, ZeroOnTheJointAxisExactlyWithoutArmature) {
  std::mt19937_64 rng(7);
  for (const double armature : {0.0, 0.05}) {
    const Model model = z_chain(armature);
    Data<double> data(model);
    const BodyIndex link1(1), link2(2);
    ASSERT_EQ(joint_subspace_coordinate(model.joint(model.body(link2).joint)), 5);
    const Mat6<double> own = model.body(link1).inertia.matrix();
    int equal = 0;
    for (int trial = 0; trial < 50; ++trial) {
      const VecX<double> q = random_configuration<double>(model, rng);
      const VecX<double> v = random_vector<double>(model.nv(), rng, 2.0);
      const VecX<double> tau = random_vector<double>(model.nv(), rng, 10.0);
      aba<double>(model, data, q, v, tau);
      bool column_is_own = true;
      for (int r = 0; r < 6; ++r) column_is_own = column_is_own && data.IA[link1](r, 5) == own(r, 5) && data.IA[link1](5, r) == own(5, r);
      equal += column_is_own ? 1 : 0;
    }
    EXPECT_EQ(equal, armature == 0 ? 50 : 0) << "armature " << armature;
  }
}

TEST(JointSubspaceCoordinate, CoordinateAxesOfOneDofJointsOnly) {
  Joint joint;
  const std::pair<Vec3<double>, int> revolute[] = {{Vec3<double>(1, 0, 0), 3}, {Vec3<double>(0, -1, 0), 4},
                                                   {Vec3<double>(0, 0, 1), 5}, {Vec3<double>(0, 0.6, 0.8), -1}};
  for (const auto& [axis, index] : revolute) {
    joint.type = JointType::Revolute;
    joint.axis = axis;
    EXPECT_EQ(joint_subspace_coordinate(joint), index) << axis.transpose();
    joint.type = JointType::Prismatic;
    EXPECT_EQ(joint_subspace_coordinate(joint), index < 0 ? -1 : index - 3) << axis.transpose();
  }
  joint.type = JointType::Floating;
  joint.axis = Vec3<double>::UnitZ();
  EXPECT_EQ(joint_subspace_coordinate(joint), -1);
}

}  // namespace
}  // namespace mbgen::test
