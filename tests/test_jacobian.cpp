// Frame, point and centre-of-mass Jacobians against finite differences of forward kinematics and
// against the body velocities that forward kinematics computes (the definition J v = velocity).
#include <gtest/gtest.h>

#include <random>

#include "test_support.hpp"

namespace mbgen::test {
namespace {

/// Angular velocity vector (world) that rotates Ra into Rb over unit time: log(Rb Ra^T).
Vec3<double> rotation_log(const Mat3<double>& Ra, const Mat3<double>& Rb) {
  Eigen::AngleAxisd aa(Rb * Ra.transpose());
  return aa.axis() * aa.angle();
}

class JacobianTest : public ::testing::TestWithParam<UrdfCase> {};

TEST_P(JacobianTest, FrameJacobiansMatchFiniteDifferencesAndVelocities) {
  const Model model = load_tree(GetParam().path, GetParam().base);
  Data<double> data(model), probe(model);
  std::mt19937_64 rng(11);
  // Central differences with h = 1e-6 have truncation error ~h^2 |d3x| ~ 1e-12 and round-off
  // ~1e-16/h ~ 1e-10: 1e-7 relative is a safe bound; the velocity check is exact to 1e-12.
  const double h = 1e-6;
  Mat6X<double> J(6, model.nv());
  for (int trial = 0; trial < 10; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    const VecX<double> v = random_vector<double>(model.nv(), rng, 1.0);
    const auto [q_plus, q_minus] = central_pair(model, q, v, h);
    compute_joint_jacobians<double>(model, data, q);
    forward_kinematics<double>(model, probe, q, v);
    Data<double> plus(model), minus(model);
    forward_kinematics<double>(model, plus, q_plus);
    update_frame_placements<double>(model, plus);
    forward_kinematics<double>(model, minus, q_minus);
    update_frame_placements<double>(model, minus);
    for (int k = 0; k < model.num_frames(); ++k) {
      const FrameIndex f(k);
      const SE3<double>& X = data.X_WF[f];
      const Vec3<double> v_fd = (plus.X_WF[f].translation - minus.X_WF[f].translation) / (2 * h);
      const Vec3<double> w_fd = rotation_log(minus.X_WF[f].rotation, plus.X_WF[f].rotation) / (2 * h);
      // Definition: the frame's velocity from the body's spatial velocity.
      const Motion<double> V_WB = data.X_WB[model.frame(f).body].act(probe.v[model.frame(f).body]);
      const Vec3<double> v_def = V_WB.linear + V_WB.angular.cross(X.translation);

      frame_jacobian<double>(model, data, f, ReferenceFrame::LocalWorldAligned, J);
      Vec6<double> Jv = J * v;
      EXPECT_LT(relative_error(Jv.head<3>(), v_fd), 1e-7) << model.frame(f).name;
      EXPECT_LT(relative_error(Jv.tail<3>(), w_fd), 1e-7) << model.frame(f).name;
      EXPECT_LT(relative_error(Jv.head<3>(), v_def), 1e-12) << model.frame(f).name;
      EXPECT_LT(relative_error(Jv.tail<3>(), V_WB.angular), 1e-12) << model.frame(f).name;

      frame_jacobian<double>(model, data, f, ReferenceFrame::Local, J);
      Jv = J * v;
      EXPECT_LT(relative_error(Jv.head<3>(), X.rotation.transpose() * v_def), 1e-12);
      EXPECT_LT(relative_error(Jv.tail<3>(), X.rotation.transpose() * V_WB.angular), 1e-12);

      frame_jacobian<double>(model, data, f, ReferenceFrame::World, J);
      Jv = J * v;
      EXPECT_LT(relative_error(Jv, V_WB.vector()), 1e-12);
    }
  }
}

TEST_P(JacobianTest, PointJacobianMatchesFiniteDifferences) {
  const Model model = load_tree(GetParam().path, GetParam().base);
  Data<double> data(model), plus(model), minus(model);
  std::mt19937_64 rng(12);
  const double h = 1e-6;
  Mat3X<double> J(3, model.nv());
  const VecX<double> q = random_configuration<double>(model, rng);
  const VecX<double> v = random_vector<double>(model.nv(), rng, 1.0);
  const auto [q_plus, q_minus] = central_pair(model, q, v, h);
  compute_joint_jacobians<double>(model, data, q);
  forward_kinematics<double>(model, plus, q_plus);
  forward_kinematics<double>(model, minus, q_minus);
  const Vec3<double> p_B(0.1, -0.05, 0.2);
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex b(k);
    const Vec3<double> v_fd = (plus.X_WB[b].act(p_B) - minus.X_WB[b].act(p_B)) / (2 * h);
    point_jacobian<double>(model, data, b, p_B, ReferenceFrame::LocalWorldAligned, J);
    EXPECT_LT(relative_error(J * v, v_fd), 1e-7) << model.body(b).name;
    point_jacobian<double>(model, data, b, p_B, ReferenceFrame::Local, J);
    EXPECT_LT(relative_error(J * v, data.X_WB[b].rotation.transpose() * v_fd), 1e-7) << model.body(b).name;
  }
}

TEST_P(JacobianTest, CenterOfMassJacobianMatchesFiniteDifferences) {
  const Model model = load_tree(GetParam().path, GetParam().base);
  Data<double> data(model), other(model);
  std::mt19937_64 rng(13);
  const double h = 1e-6;
  const VecX<double> q = random_configuration<double>(model, rng);
  const VecX<double> v = random_vector<double>(model.nv(), rng, 1.0);
  const auto [q_plus, q_minus] = central_pair(model, q, v, h);
  const Vec3<double> c_plus = center_of_mass<double>(model, other, q_plus);
  const Vec3<double> c_minus = center_of_mass<double>(model, other, q_minus);
  jacobian_center_of_mass<double>(model, data, q);
  center_of_mass<double>(model, other, q, v);
  EXPECT_LT(relative_error(data.Jcom * v, (c_plus - c_minus) / (2 * h)), 1e-7);
  EXPECT_LT(relative_error(data.Jcom * v, other.vcom), 1e-12);
  EXPECT_LT(relative_error(data.com, other.com), 1e-14);
  EXPECT_NEAR(data.mass, model.total_mass(), 1e-12 * model.total_mass());
}

INSTANTIATE_TEST_SUITE_P(AllUrdfs, JacobianTest, ::testing::ValuesIn(all_urdf_cases()), urdf_case_name);

}  // namespace
}  // namespace mbgen::test
