// The analytic derivatives of the inverse and forward dynamics (rnea_derivatives.hpp,
// aba_derivatives.hpp) against independent derivatives:
//  - forward-mode dual numbers (Eigen's AutoDiffScalar) pushed through the generic rnea() and aba()
//    (exact to round-off, autodiff_reference.hpp):
//    1e-11 relative (max-norm of the difference over the reference's max-norm), on every robot
//    with fixed and floating base, and with geared rotors (armature and body models) on every
//    1-DoF joint, the sweep in the root's axes (and with rotor bodies in the world's: SweepAxes);
//  - central finite differences along `integrate` (the stated tangent convention): 1e-6;
//  the forward dynamics' derivatives weighted by M (weighted_relative: a solve with an
//  ill-conditioned M is exact only in the directions M resists);
//  - tau equal to rnea's (1e-12) and M^-1 times M the identity (1e-12);
//  - no allocation in either call (malloc guard).
#include <gtest/gtest.h>

#include <random>

#include "autodiff_reference.hpp"
#include "derivative_errors.hpp"
#include "malloc_guard.hpp"
#include "mbgen/algorithm/aba_derivatives.hpp"
#include "test_support.hpp"
#include "three_joint_arm.hpp"

namespace mbgen::test {
namespace {

enum class Drives { None, Armature, Body };

/// A drive on every 1-DoF joint (gear ratios 50..160, rotor inertias 1e-5..1e-4 kg m^2).
Model with_drives(Model model, Drives drives, std::mt19937_64& rng) {
  if (drives == Drives::None) return model;
  std::uniform_real_distribution<double> ratio(50, 160), inertia(1e-5, 1e-4);
  for (int j = 1; j < model.num_joints(); ++j) {
    Joint& joint = model.mutable_joint(JointIndex(j));
    if (joint.nv != 1) continue;
    const double N = ratio(rng), I = inertia(rng);
    if (drives == Drives::Armature) {
      joint.armature = N * N * I;
    } else {
      joint.rotor_gear_ratio = N;
      joint.rotor_inertia = I;
    }
  }
  model.update_structure();
  return model;
}

class DynamicsDerivativesTest : public ::testing::TestWithParam<UrdfCase> {};

TEST_P(DynamicsDerivativesTest, MatchDualNumbers) {
  std::mt19937_64 rng(54);
  for (const auto& [drives, axes] : {std::pair{Drives::None, SweepAxes::root}, std::pair{Drives::Armature, SweepAxes::root},
                                     std::pair{Drives::Body, SweepAxes::root}, std::pair{Drives::Body, SweepAxes::world}}) {
    SCOPED_TRACE(drives == Drives::None ? "no drives" : drives == Drives::Armature ? "armature" : "rotor bodies");
    SCOPED_TRACE(axes == SweepAxes::root ? "the root's axes" : "the world's axes");
    const Model model = with_drives(load_tree(GetParam().path, GetParam().base), drives, rng);
    Data<double> data(model), other(model);
    DynamicsDerivatives<double> d(model, axes);
    for (int trial = 0; trial < 3; ++trial) {
      const VecX<double> q = random_configuration<double>(model, rng);
      const VecX<double> v = random_vector<double>(model.nv(), rng, 2.0);
      const VecX<double> a = random_vector<double>(model.nv(), rng, 5.0);
      const VecX<double> tau = random_vector<double>(model.nv(), rng, 10.0);
      const DualJacobians ref = dual_jacobians(model, q, v, a, tau);

      inverse_dynamics_derivatives<double>(model, data, d, q, v, a);
      EXPECT_LT(relative_error(d.tau, rnea<double>(model, other, q, v, a)), 1e-12);
      EXPECT_LT(max_relative(d.dtau_dq, ref.dtau_dq), 1e-11);
      EXPECT_LT(max_relative(d.dtau_dv, ref.dtau_dv), 1e-11);

      forward_dynamics_derivatives<double>(model, data, d, q, v, tau);
      const MatX<double> M = crba<double>(model, other, q);
      // qdd comes from M's factor, against the articulated-body algorithm: weighted by M, as the
      // derivatives below (on 5bar_linkage the two differ by up to 5e-11 unweighted).
      EXPECT_LT(weighted_relative(M, d.ddq, aba<double>(model, other, q, v, tau)), 1e-13);
      EXPECT_LT(weighted_relative(M, d.dddq_dq, ref.dddq_dq), 1e-11);
      EXPECT_LT(weighted_relative(M, d.dddq_dv, ref.dddq_dv), 1e-11);
      EXPECT_LT(weighted_relative(M, d.Minv, ref.dddq_dtau), 1e-11);
      EXPECT_LT((d.Minv * M - MatX<double>::Identity(model.nv(), model.nv())).cwiseAbs().maxCoeff(), 1e-12 * M.norm() * d.Minv.norm());
    }
  }
}

// The tangent convention, by central differences along integrate (h = 1e-6 in q: truncation h^2
// times the third derivative against round-off eps / h; 1e-6 relative holds with margin).
TEST_P(DynamicsDerivativesTest, MatchCentralDifferencesAlongIntegrate) {
  std::mt19937_64 rng(55);
  const Model model = load_tree(GetParam().path, GetParam().base);
  Data<double> data(model), other(model);
  DynamicsDerivatives<double> d(model);
  const VecX<double> q = random_configuration<double>(model, rng);
  const VecX<double> v = random_vector<double>(model.nv(), rng, 2.0);
  const VecX<double> tau = random_vector<double>(model.nv(), rng, 10.0);
  forward_dynamics_derivatives<double>(model, data, d, q, v, tau);
  const int nv = model.nv();
  const double h = 1e-6;
  MatX<double> fd_q(nv, nv), fd_v(nv, nv);
  for (int k = 0; k < nv; ++k) {
    const VecX<double> e = VecX<double>::Unit(nv, k);
    const CentralPair p = central_pair(model, q, e, h);
    fd_q.col(k) = (aba<double>(model, other, p.plus, v, tau) - VecX<double>(aba<double>(model, other, p.minus, v, tau))) / (2 * h);
    // qdd is quadratic in v, so central differences in v have no truncation error: a larger step
    // only shrinks the round-off (the delta robot's light links accelerate at 1e5 in some directions).
    const double hv = 1e-3;
    fd_v.col(k) = (aba<double>(model, other, q, v + hv * e, tau) - VecX<double>(aba<double>(model, other, q, v - hv * e, tau))) / (2 * hv);
  }
  const MatX<double> M = crba<double>(model, other, q);
  EXPECT_LT(weighted_relative(M, d.dddq_dq, fd_q), 1e-6);
  EXPECT_LT(weighted_relative(M, d.dddq_dv, fd_v), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(AllUrdfs, DynamicsDerivativesTest, ::testing::ValuesIn(all_urdf_cases()), urdf_case_name);

// A fixed arm whose first joint's frame is turned in the world's, with a rotor body on every joint:
// the rotor on the world reads the world's pose in the sweep's axes, which in the root's axes is
// the root's pose inverted (not the identity: every robot of the suite has an unturned first joint
// frame, where the two give the same spin axis). The rotor's direction does not enter tau (only
// w . w does), so the sweep's columns are compared too: in the root's axes, turned into the
// world's, they are the world sweep's.
Model turned_arm_with_rotors() {
  Inertia<double> link;
  link.mass = 1.2;
  link.com = Vec3<double>(0.05, 0.1, -0.02);
  link.inertia_com = Vec3<double>(0.02, 0.015, 0.01).asDiagonal();
  return three_joint_arm(link, [](Joint& joint, int j) {
    joint.X_PJ.rotation = Eigen::AngleAxisd(0.4 + 0.3 * j, Vec3<double>(1, -2, 0.5).normalized()).toRotationMatrix();
    joint.X_PJ.translation = Vec3<double>(0.1, -0.05, 0.3);
    joint.rotor_gear_ratio = 60.0 + 20 * j;
    joint.rotor_inertia = 4e-5;
  });
}

TEST(DynamicsDerivatives, RootAxesTurnTheWorldsRotorIntoThem) {
  std::mt19937_64 rng(57);
  const Model model = turned_arm_with_rotors();
  Data<double> data(model);
  DynamicsDerivatives<double> root(model, SweepAxes::root), world(model, SweepAxes::world);
  ASSERT_TRUE(root.root_axes);
  for (int trial = 0; trial < 3; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    const VecX<double> v = random_vector<double>(model.nv(), rng, 2.0);
    const VecX<double> a = random_vector<double>(model.nv(), rng, 5.0);
    const DualJacobians ref = dual_jacobians(model, q, v, a, a);
    inverse_dynamics_derivatives<double>(model, data, root, q, v, a);
    inverse_dynamics_derivatives<double>(model, data, world, q, v, a);
    for (const DynamicsDerivatives<double>* d : {&root, &world}) {
      EXPECT_LT(max_relative(d->dtau_dq, ref.dtau_dq), 1e-11);
      EXPECT_LT(max_relative(d->dtau_dv, ref.dtau_dv), 1e-11);
    }
    EXPECT_LT(relative_error(root.tau, world.tau), 1e-13);
    // Three joints' columns, then three rotors' [0; N w]: a spin, whose linear part no rotor's
    // inertia (I_r w w^T alone, the same about every point) reads, and which is zero in either axes.
    ASSERT_EQ(root.J.size(), 6u);
    for (std::size_t c = 0; c < root.J.size(); ++c) {
      const Motion<double> turned = root.X[kWorldBody].act_inv(root.J[c]);
      const Vec3<double> linear = c < 3 ? turned.linear : root.J[c].linear;
      EXPECT_LT((turned.angular - world.J[c].angular).norm() + (linear - world.J[c].linear).norm(), 1e-13) << c;
    }
  }
}

TEST(DynamicsDerivatives, AllocateNothing) {
  std::mt19937_64 rng(56);
  const Model model = with_drives(load_tree(MBGEN_SOURCE_DIR "/robots/lola/lola.urdf", gen::BaseType::Floating), Drives::Body, rng);
  Data<double> data(model);
  DynamicsDerivatives<double> d(model);
  const VecX<double> q = random_configuration<double>(model, rng);
  const VecX<double> v = random_vector<double>(model.nv(), rng, 2.0);
  const VecX<double> tau = random_vector<double>(model.nv(), rng, 10.0);
  MallocGuard guard;
  inverse_dynamics_derivatives<double>(model, data, d, q, v, tau);
  forward_dynamics_derivatives<double>(model, data, d, q, v, tau);
  EXPECT_EQ(guard.count(), 0u);
}

}  // namespace
}  // namespace mbgen::test
