// Geared rotors (runtime/include/mbgen/algorithm/rotor.hpp), both fidelities.
//  - Definition: kinetic_energy (body velocities and rotor spin rates) = 1/2 v^T M v from CRBA.
//  - Lagrange's equations by finite differences of CRBA and the energy: RNEA's bias, rotor
//    gyroscopic terms included, must equal d/dt(dT/dqd) - dT/dq + dV/dq.
//  - ABA against CRBA and RNEA with rotors on every joint (fixed and floating base).
//  - Armature vs body model on a three-joint arm with a closed form: identical at q = 0 and zero
//    rates; at high rates they differ by the rotor's gyroscopic terms, exactly as derived below.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "load/load_error.hpp"
#include "test_support.hpp"
#include "three_joint_arm.hpp"

namespace mbgen::test {
namespace {

enum class RotorModel { Armature, Body };

/// The shared robot with a drive on every 1-DoF joint (gear ratios 50..160, rotor inertias
/// 1e-5..1e-4 kg m^2, the range of harmonic drives).
Model with_drives(Model model, RotorModel kind, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> ratio(50, 160), inertia(1e-5, 1e-4);
  for (int j = 1; j < model.num_joints(); ++j) {
    Joint& joint = model.mutable_joint(JointIndex(j));
    if (joint.nv != 1) continue;
    const double N = ratio(rng), I = inertia(rng);
    if (kind == RotorModel::Armature) {
      joint.armature = N * N * I;
    } else {
      joint.rotor_gear_ratio = N;
      joint.rotor_inertia = I;
    }
  }
  return model;
}

class RotorTest : public ::testing::TestWithParam<UrdfCase> {};

TEST_P(RotorTest, EnergyCrbaRneaAndAbaAgree) {
  std::mt19937_64 rng(5);
  for (RotorModel kind : {RotorModel::Armature, RotorModel::Body}) {
    const Model model = with_drives(load_tree(GetParam().path, GetParam().base), kind, rng);
    Data<double> data(model), other(model);
    for (int trial = 0; trial < 10; ++trial) {
      const VecX<double> q = random_configuration<double>(model, rng);
      const VecX<double> v = random_vector<double>(model.nv(), rng, 2.0);
      const VecX<double> tau = random_vector<double>(model.nv(), rng, 10.0);
      const MatX<double> M = crba<double>(model, data, q);
      // Energy from its definition vs the mass matrix: same sums, 1e-12 relative.
      const double T = kinetic_energy<double>(model, other, q, v);
      EXPECT_NEAR(T, 0.5 * v.dot(M * v), 1e-12 * T);
      // ABA vs M^-1 (tau - h): normwise backward error, as in test_aba.cpp.
      const VecX<double> h = nonlinear_effects<double>(model, other, q, v);
      const VecX<double> ddq = aba<double>(model, data, q, v, tau);
      const double scale = M.norm() * ddq.norm() + tau.norm() + h.norm();
      EXPECT_LT((M * ddq + h - tau).norm() / scale, 1e-10);
    }
  }
}

TEST_P(RotorTest, RneaSatisfiesLagrangesEquations) {
  if (GetParam().base == gen::BaseType::Floating) GTEST_SKIP() << "fixed base: q and v are the same coordinates";
  std::mt19937_64 rng(6);
  const Model model = with_drives(load_tree(GetParam().path, GetParam().base), RotorModel::Body, rng);
  Data<double> data(model);
  const int n = model.nv();
  const VecX<double> q = random_configuration<double>(model, rng);
  const VecX<double> v = random_vector<double>(n, rng, 2.0);
  const VecX<double> a = random_vector<double>(n, rng, 2.0);
  // tau = M a + (dM/dt) v - dT/dq + dV/dq, the derivatives by central differences (h = 1e-6:
  // truncation ~1e-12, round-off ~1e-10 relative): 1e-7 relative to the size of the terms.
  const double step = 1e-6;
  const MatX<double> M = crba<double>(model, data, q);
  MatX<double> Mdot = MatX<double>::Zero(n, n);
  VecX<double> dT = VecX<double>::Zero(n), dV = VecX<double>::Zero(n);
  for (int k = 0; k < n; ++k) {
    VecX<double> qp = q, qm = q;
    qp[k] += step;
    qm[k] -= step;
    const MatX<double> M_plus = crba<double>(model, data, qp);  // a copy: crba returns data.M
    Mdot += (M_plus - crba<double>(model, data, qm)) * (v[k] / (2 * step));
    dT[k] = (kinetic_energy<double>(model, data, qp, v) - kinetic_energy<double>(model, data, qm, v)) / (2 * step);
    dV[k] = (potential_energy<double>(model, data, qp) - potential_energy<double>(model, data, qm)) / (2 * step);
  }
  const VecX<double> lagrange = M * a + Mdot * v - dT + dV;
  const VecX<double> tau = rnea<double>(model, data, q, v, a);
  EXPECT_LT((tau - lagrange).norm() / ((M * a).norm() + (Mdot * v).norm() + dV.norm()), 1e-7);
}

INSTANTIATE_TEST_SUITE_P(AllUrdfs, RotorTest, ::testing::ValuesIn(all_urdf_cases()), urdf_case_name);

/// Arm: joint 1 about z (from the world), joint 2 about y, joint 3 about x, all at one point.
/// Joint 3's rotor sits in link 2 and spins about x at N qd3. With w = x in link 2,
/// w . w_2 = -qd1 sin q2, so the rotor adds T_extra = 1/2 I (qd1 sin q2)^2 - N I qd3 qd1 sin q2
/// beyond the armature's 1/2 N^2 I qd3^2. At q = 0 Lagrange's equations give the extra bias
///   tau_1 = -N I qd2 qd3,  tau_2 = N I qd1 qd3,  tau_3 = -N I qd1 qd2,
/// and the extra mass-matrix entry M_13 = -N I sin q2 (zero at q2 = 0).
Model gyroscope_arm(RotorModel kind, double N, double I) {
  Inertia<double> link;
  link.mass = 1.5;
  link.com = Vec3<double>(0.1, 0.02, -0.05);
  link.inertia_com = Vec3<double>(0.02, 0.03, 0.04).asDiagonal();
  return three_joint_arm(link, [&](Joint& joint, int j) {
    if (j != 2) return;
    if (kind == RotorModel::Armature) {
      joint.armature = N * N * I;
    } else {
      joint.rotor_gear_ratio = N;
      joint.rotor_inertia = I;
    }
  });
}

TEST(RotorModels, AgreeAtRestAndDifferByTheGyroscopicTerms) {
  const double N = 100, I = 5e-5;
  const Model arm = gyroscope_arm(RotorModel::Armature, N, I), body = gyroscope_arm(RotorModel::Body, N, I);
  Data<double> da(arm), db(body);
  const VecX<double> zero = VecX<double>::Zero(3);
  // At q = 0 and zero rates the two models are the same system (1e-15: identical sums).
  EXPECT_LT((crba<double>(arm, da, zero) - crba<double>(body, db, zero)).norm(), 1e-15);
  const VecX<double> tau = (VecX<double>(3) << 1.0, -2.0, 0.5).finished();
  EXPECT_LT((aba<double>(arm, da, zero, zero, tau) - aba<double>(body, db, zero, zero, tau)).norm(), 1e-12);
  // At high rates (rotor at N qd3 = 2000 rad/s) the bias differs by the gyroscopic terms.
  const VecX<double> v = (VecX<double>(3) << 3.0, -4.0, 20.0).finished();
  const VecX<double> diff = nonlinear_effects<double>(body, db, zero, v) - nonlinear_effects<double>(arm, da, zero, v);
  const VecX<double> expected = (VecX<double>(3) << -N * I * v[1] * v[2], N * I * v[0] * v[2], -N * I * v[0] * v[1]).finished();
  EXPECT_LT((diff - expected).norm(), 1e-13 * expected.norm()) << diff.transpose() << " vs " << expected.transpose();
  // Away from q2 = 0 the inertia couples joints 1 and 3 through the rotor: M_13 = -N I sin q2.
  const VecX<double> q = (VecX<double>(3) << 0.3, 0.7, -0.2).finished();
  const MatX<double> dM = crba<double>(body, db, q) - crba<double>(arm, da, q);
  EXPECT_NEAR(dM(0, 2), -N * I * std::sin(q[1]), 1e-15);
  EXPECT_NEAR(dM(0, 0), I * std::sin(q[1]) * std::sin(q[1]), 1e-15);
  EXPECT_NEAR(dM(2, 2), 0.0, 1e-15);
}

TEST(RotorModels, DrivesComeFromTheExtrasAndTheSceneChoosesTheModel) {
  const std::string data = MBGEN_TEST_DATA;
  gen::LoadOptions options;
  options.extras_file = data + "/extras/drives.yaml";
  const gen::Description d = gen::load_description(data + "/tiny_arm.urdf", options);
  const Joint& shoulder = d.model.joint(*d.model.find_joint("shoulder"));
  const Joint& elbow = d.model.joint(*d.model.find_joint("elbow"));
  // scene: rotors: body turns the armature drive of the shoulder into a rotor body too.
  EXPECT_EQ(shoulder.armature, 0.0);
  EXPECT_EQ(shoulder.rotor_gear_ratio, 100.0);
  EXPECT_EQ(shoulder.rotor_inertia, 2e-5);
  EXPECT_EQ(elbow.rotor_gear_ratio, -50.0);
  EXPECT_EQ(elbow.rotor_inertia, 1e-5);
}

/// `scene: rotors: none` leaves every drive out: the model is the URDF's alone (its mass matrix
/// equals the drive-free load's), and the reduction says so.
TEST(RotorModels, RotorsNoneLeavesTheDrivesOut) {
  const std::string data = MBGEN_TEST_DATA;
  std::ifstream in(data + "/extras/drives.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const std::size_t at = yaml.find("rotors: body");
  ASSERT_NE(at, std::string::npos) << yaml;
  yaml.replace(at, 12, "rotors: none");
  const std::string path = (std::filesystem::temp_directory_path() / "mbgen_test_rotors_none.yaml").string();
  { std::ofstream(path) << yaml; }
  gen::LoadOptions with, without;
  with.extras_file = path;
  without.pick_up_robot_yaml = false;
  const gen::Description none = gen::load_description(data + "/tiny_arm.urdf", with);
  const gen::Description bare = gen::load_description(data + "/tiny_arm.urdf", without);
  const gen::Description drives = gen::load_description(data + "/tiny_arm.urdf", [&] {
    gen::LoadOptions o;
    o.extras_file = data + "/extras/drives.yaml";
    return o;
  }());
  Data<double> dn(none.model), db(bare.model), dd(drives.model);
  const VecX<double> q = (VecX<double>(bare.model.nq()) << 0.3, 0.7, -0.2).finished();
  EXPECT_EQ(crba<double>(none.model, dn, q), crba<double>(bare.model, db, q));
  EXPECT_GT((crba<double>(drives.model, dd, q) - crba<double>(bare.model, db, q)).norm(), 1e-3);  // the drives matter
  ASSERT_EQ(none.reductions.size(), 1u);
  EXPECT_NE(none.reductions[0].find("rotors: none"), std::string::npos) << none.reductions[0];
}

}  // namespace
}  // namespace mbgen::test
