// Differential IK (runtime/include/mbgen/control/differential_ik.hpp), checked against
// independent computations:
//  - the primary stack (both feet, centre of mass, torso orientation) of the floating-base TALOS
//    is achieved exactly (1e-10) at a regular pose, checked with Jacobians computed apart from the
//    controller; the base moves when both feet are asked to;
//  - weights: the weighted minimum-norm solution W^-1 J^T (J W^-1 J^T)^-1 xd (LDL^T), 1e-9;
//  - the secondary velocity against the KKT system of its stated cost (dense LU), 1e-8, and the
//    null-space property J v_secondary = 0 (1e-12 |J| |v_secondary|);
//  - angular-momentum tracking in a closed-loop kinematic simulation (1 s at 1 kHz): the
//    centroidal angular momentum (computed apart) follows a desired sinusoid with an RMS error
//    at least 100 times smaller than without the objective, while feet stay put (1e-9 m);
//  - velocity limits: respected, the task velocity scaled, not distorted;
//  - a model with closed loops (Lola, bent knees): J T c = xd and J T c_secondary = 0 to 1e-12
//    relative to |J T| |c| (T's entries reach ~10: round-off scales with them), the loops stay
//    closed to first order (Phi_q v = 0, 1e-10), with collision avoidance and momentum tracking
//    active, also over 300 steps of a closed-loop simulation that re-closes the loops by Newton;
//  - a singular pose (stretched arm, unreachable target): finite, bounded velocities;
//  - non-finite input reported, zero commanded; float instantiation; no allocation in step();
//    construction errors by their text.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cstdio>
#include <random>

#include "malloc_guard.hpp"
#include "mbgen/control/differential_ik.hpp"
#include "collision/collision_scene.hpp"
#include "model/load_description.hpp"
#include "lola.hpp"
#include "lola_ik_scenario.hpp"   // bench/: the scenario ik_step/lola times
#include "talos_ik_scenario.hpp"  // bench/: the scenario ik_step/talos times
#include "test_support.hpp"

namespace mbgen::test {
namespace {

using namespace mbgen::control;

Model talos() { return load_tree(shared_robot("talos/talos_reduced.urdf"), gen::BaseType::Floating); }

using scenario::set_targets_near;
using scenario::talos_pose;
using scenario::talos_tasks;

TEST(DifferentialIk, PrimaryTasksAreAchievedExactlyAndMoveTheBase) {
  const Model model = talos();
  const VecX<double> q = talos_pose(model, 1);
  DifferentialIk<double> ik(model, talos_tasks());
  set_targets_near(ik, model, q, 2);
  VecX<double> v(model.nv());
  const StepReport report = ik.step(q, v);
  ASSERT_TRUE(report.ok);
  EXPECT_EQ(report.rank, 18);
  ASSERT_GT(report.smallest_singular_value, 0.01);  // outside the singular region: no damping
  // Independent check: each task's Jacobian from a fresh Data, its desired velocity by hand.
  Data<double> data(model);
  compute_joint_jacobians<double>(model, data, q);
  const Mat3X<double> Jcom = jacobian_center_of_mass<double>(model, data, q);
  Mat6X<double> J(6, model.nv());
  double worst = 0;
  for (int i = 0; i < ik.num_tasks(); ++i) {
    const Task& t = ik.task(i);
    const TaskTarget<double>& target = ik.target(i);
    const double k = t.spec.gain;
    if (t.spec.kind == TaskKind::CenterOfMass) {
      const Vec3<double> want = target.velocity.head<3>() + k * (target.position - data.com);
      worst = std::max(worst, (Jcom * v - want).cwiseAbs().maxCoeff());
      continue;
    }
    frame_jacobian<double>(model, data, t.frame, ReferenceFrame::LocalWorldAligned, J);
    const SE3<double>& X = data.X_WF[t.frame];
    const Eigen::AngleAxisd error(target.rotation * X.rotation.transpose());
    const Vec3<double> w = target.velocity.tail<3>() + k * error.angle() * error.axis();
    const Vec3<double> lin = target.velocity.head<3>() + k * (target.position - X.translation);
    if (t.spec.kind != TaskKind::FrameOrientation) worst = std::max(worst, (J.topRows<3>() * v - lin).cwiseAbs().maxCoeff());
    if (t.spec.kind != TaskKind::FramePosition) worst = std::max(worst, (J.bottomRows<3>() * v - w).cwiseAbs().maxCoeff());
  }
  std::printf("  TALOS, 18 primary rows: max |J v - xd| = %.2e (|xd| = %.2f), sigma_min %.3f\n", worst,
              ik.primary_velocity().norm(), report.smallest_singular_value);
  EXPECT_LT(worst, 1e-10);

  // Both feet asked to slide 0.1 m/s forward, CoM with them: the base follows.
  DifferentialIk<double> feedforward(model, talos_tasks(0.0));
  for (int i = 0; i < 4; ++i) feedforward.target(i).velocity = i < 3 ? Vec6<double>((Vec6<double>() << 0.1, 0, 0, 0, 0, 0).finished()) : Vec6<double>::Zero();
  ASSERT_TRUE(feedforward.step(q, v).ok);
  const Vec3<double> base_velocity_world = quaternion_to_rotation<double>(q[3], q[4], q[5], q[6]) * v.head<3>();
  std::printf("  feet and CoM at 0.1 m/s: base at (%.3f, %.3f, %.3f) m/s, joints up to %.3f rad/s\n", base_velocity_world.x(),
              base_velocity_world.y(), base_velocity_world.z(), v.tail(model.nv() - 6).cwiseAbs().maxCoeff());
  // A rigid translation satisfies every task; the minimum-norm answer shares the motion between
  // base and joints, but most of it is the base's.
  EXPECT_GT(base_velocity_world.x(), 0.05);
}

TEST(DifferentialIk, PoseErrorsDecayExponentially) {
  // Targets 5 cm and 0.1 rad away, no feed-forward, gain 10/s, 0.5 s of explicit Euler at 1 kHz:
  // every error (position, orientation, CoM) shrinks as (1 - 10 dt)^500 = 6.6e-3 would have it,
  // which checks the sign and frame of the errors, the orientation log included.
  const Model model = talos();
  VecX<double> q = talos_pose(model, 21), v(model.nv()), next(model.nq());
  DifferentialIk<double> ik(model, talos_tasks(10.0));
  set_targets_near(ik, model, q, 22);
  for (int i = 0; i < ik.num_tasks(); ++i) ik.target(i).velocity.setZero();
  auto errors = [&](const VecX<double>& at) {
    Data<double> data(model);
    center_of_mass<double>(model, data, at);
    update_frame_placements<double>(model, data);
    std::vector<double> e;
    for (int i = 0; i < ik.num_tasks(); ++i) {
      const Task& t = ik.task(i);
      const TaskTarget<double>& target = ik.target(i);
      if (t.spec.kind == TaskKind::CenterOfMass) {
        e.push_back((target.position - data.com).norm());
        continue;
      }
      if (t.spec.kind != TaskKind::FrameOrientation) e.push_back((target.position - data.X_WF[t.frame].translation).norm());
      if (t.spec.kind != TaskKind::FramePosition)
        e.push_back(Eigen::AngleAxisd(target.rotation * data.X_WF[t.frame].rotation.transpose()).angle());
    }
    return e;
  };
  const std::vector<double> before = errors(q);
  for (int k = 0; k < 500; ++k) {
    ASSERT_TRUE(ik.step(q, v).ok);
    integrate<double>(model, q, v * 1e-3, next);
    q = next;
  }
  const std::vector<double> after = errors(q);
  double worst = 0;
  for (std::size_t i = 0; i < before.size(); ++i) worst = std::max(worst, after[i] / before[i]);
  std::printf("  6 pose errors after 0.5 s at gain 10/s: worst ratio to the start %.2e (linear theory 6.6e-3)\n", worst);
  EXPECT_LT(worst, 8e-3);
  EXPECT_GT(worst, 5e-3);  // not faster than the gain says either: the feedback is what moves it
}

TEST(DifferentialIk, WeightsGiveTheWeightedMinimumNormSolution) {
  const Model model = talos();
  const VecX<double> q = talos_pose(model, 3);
  DifferentialIkOptions options;
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0.5, 20.0);
  for (int i = 0; i < model.nv(); ++i) options.weights.push_back(u(rng));
  DifferentialIk<double> ik(model, talos_tasks(), options);
  set_targets_near(ik, model, q, 5);
  VecX<double> v(model.nv());
  ASSERT_TRUE(ik.step(q, v).ok);
  const MatX<double>& J = ik.primary_jacobian();
  const VecX<double> w_inv = Eigen::Map<const VecX<double>>(options.weights.data(), model.nv()).cwiseInverse();
  const MatX<double> JWinv = J * w_inv.asDiagonal();
  const VecX<double> reference = JWinv.transpose() * (JWinv * J.transpose()).ldlt().solve(ik.primary_velocity());
  const double error = (v - reference).norm() / reference.norm();
  std::printf("  weighted minimum norm: relative difference to the closed form %.2e\n", error);
  EXPECT_LT(error, 1e-9);
}

// Per-axis weights w: the cost's momentum term becomes rho/2 |diag(sqrt(w)) (Bk (v1 + x) - k_des)|^2;
// (1, 1, 1) is the plain objective, (0, 0, 1) the vertical component alone.
class SecondaryVelocity : public ::testing::TestWithParam<Vec3<double>> {};

TEST_P(SecondaryVelocity, MinimisesItsCostInTheNullSpace) {
  const Model model = talos();
  const VecX<double> q = talos_pose(model, 6);
  const Vec3<double> w = GetParam();
  DifferentialIkOptions options;
  options.angular_momentum.enabled = true;
  options.angular_momentum.weight = 50.0;
  options.angular_momentum.axis_weights = {w.x(), w.y(), w.z()};
  DifferentialIk<double> ik(model, talos_tasks(), options);
  set_targets_near(ik, model, q, 7);
  ik.angular_momentum_target = Vec3<double>(4.0, -3.0, 2.0);
  VecX<double> v(model.nv());
  ASSERT_TRUE(ik.step(q, v).ok);
  const MatX<double>& J = ik.primary_jacobian();
  const VecX<double> secondary = ik.secondary_velocity();
  const VecX<double> primary = v - secondary;
  // KKT of  min 1/2 |x|^2 + rho/2 |W^1/2 (Bk (v1 + x) - k_des)|^2  s.t.  J x = 0  (W = I, no collision term).
  Data<double> data(model);
  const Mat3X<double> Bk = centroidal_momentum_matrix<double>(model, data, q).bottomRows<3>();
  const int n = model.nv(), m = static_cast<int>(J.rows());
  MatX<double> kkt = MatX<double>::Zero(n + m, n + m);
  kkt.topLeftCorner(n, n) = MatX<double>::Identity(n, n) + 50.0 * Bk.transpose() * w.asDiagonal() * Bk;
  kkt.topRightCorner(n, m) = J.transpose();
  kkt.bottomLeftCorner(m, n) = J;
  VecX<double> rhs = VecX<double>::Zero(n + m);
  rhs.head(n) = 50.0 * Bk.transpose() * w.asDiagonal() * (ik.angular_momentum_target - Bk * primary);
  const VecX<double> reference = kkt.fullPivLu().solve(rhs).head(n);
  const double error = (secondary - reference).norm() / reference.norm();
  const double leak = (J * secondary).cwiseAbs().maxCoeff() / (J.norm() * secondary.norm());
  std::printf("  axis weights (%g, %g, %g): secondary vs KKT: relative difference %.2e; |J v_secondary| / (|J| |v_secondary|) = %.2e\n",
              w.x(), w.y(), w.z(), error, leak);
  EXPECT_LT(error, 1e-8);
  EXPECT_LT(leak, 1e-12);
  EXPECT_LT((J * v - ik.primary_velocity()).cwiseAbs().maxCoeff(), 1e-10);
}

INSTANTIATE_TEST_SUITE_P(DifferentialIk, SecondaryVelocity,
                         ::testing::Values(Vec3<double>(1, 1, 1), Vec3<double>(0, 0, 1), Vec3<double>(0.5, 2, 0)));

TEST(DifferentialIk, AngularMomentumFollowsItsTargetWhileTheFeetStayPut) {
  const Model model = talos();
  const VecX<double> q0 = talos_pose(model, 8);
  auto run = [&](bool track, double& rms_error, double& foot_drift, double& worst_primary) {
    DifferentialIkOptions options;
    options.angular_momentum.enabled = track;
    options.angular_momentum.weight = 1e4;
    DifferentialIk<double> ik(model, talos_tasks(20.0), options);
    Data<double> data(model), check(model);
    center_of_mass<double>(model, data, q0);
    update_frame_placements<double>(model, data);
    for (int i = 0; i < ik.num_tasks(); ++i) {
      const Task& t = ik.task(i);
      ik.target(i).position = t.spec.kind == TaskKind::CenterOfMass ? data.com : data.X_WF[t.frame].translation;
      if (t.spec.kind != TaskKind::CenterOfMass) ik.target(i).rotation = data.X_WF[t.frame].rotation;
    }
    const Vec3<double> com0 = data.com;
    const int com = ik.task_index("com");
    VecX<double> q = q0, v(model.nv()), next(model.nq());
    const double dt = 1e-3, pi = 3.141592653589793;
    double sum = 0;
    worst_primary = 0;
    for (int k = 0; k < 1000; ++k) {
      const double t = k * dt;
      // The CoM sways 2 cm sideways; the angular momentum should swing about the vertical.
      ik.target(com).position = com0 + Vec3<double>(0, 0.02 * std::sin(2 * pi * t), 0);
      ik.target(com).velocity.head<3>() = Vec3<double>(0, 0.02 * 2 * pi * std::cos(2 * pi * t), 0);
      const Vec3<double> k_des(0.0, 0.0, 2.0 * std::sin(2 * pi * t));
      ik.angular_momentum_target = k_des;
      EXPECT_TRUE(ik.step(q, v).ok);
      worst_primary = std::max(worst_primary, (ik.primary_jacobian() * v - ik.primary_velocity()).cwiseAbs().maxCoeff());
      const Vec3<double> h = centroidal_momentum<double>(model, check, q, v).tail<3>();
      sum += (h - k_des).squaredNorm();
      integrate<double>(model, q, v * dt, next);
      q = next;
    }
    rms_error = std::sqrt(sum / 1000);
    forward_kinematics<double>(model, check, q);
    update_frame_placements<double>(model, check);
    foot_drift = 0;
    for (const char* foot : {"left_sole_link", "right_sole_link"}) {
      const FrameIndex f = model.frame_index(foot);
      foot_drift = std::max(foot_drift, (check.X_WF[f].translation - data.X_WF[f].translation).norm());
    }
  };
  double plain_error, plain_drift, plain_primary, tracked_error, tracked_drift, tracked_primary;
  run(false, plain_error, plain_drift, plain_primary);
  run(true, tracked_error, tracked_drift, tracked_primary);
  std::printf("  angular momentum RMS error: %.4f without, %.2e with tracking (ratio %.1e); foot drift %.1e / %.1e m; "
              "|J v - xd| <= %.1e\n",
              plain_error, tracked_error, tracked_error / plain_error, plain_drift, tracked_drift, tracked_primary);
  EXPECT_GT(plain_error, 1.0);  // without the objective the momentum does not follow a 2 kg m^2/s swing
  EXPECT_LT(tracked_error, plain_error / 100);
  EXPECT_LT(tracked_drift, 2e-6);  // explicit Euler at 1 kHz on a fixed-foot task with gain 20/s (1.0e-6 seen)
  EXPECT_LT(tracked_primary, 1e-10);
}

TEST(DifferentialIk, VelocityLimitsScaleTheWholeVelocity) {
  const Model model = talos();
  const VecX<double> q = talos_pose(model, 9);
  DifferentialIk<double> free(model, talos_tasks());
  set_targets_near(free, model, q, 10);
  VecX<double> v_free(model.nv()), v(model.nv());
  ASSERT_TRUE(free.step(q, v_free).ok);
  DifferentialIkOptions options;
  for (int i = 0; i < model.nv(); ++i) options.velocity_limits.push_back(0.5 * v_free.cwiseAbs().maxCoeff());
  DifferentialIk<double> limited(model, talos_tasks(), options);
  set_targets_near(limited, model, q, 10);
  const StepReport report = limited.step(q, v);
  EXPECT_NEAR(report.limit_scale, 0.5, 1e-12);
  EXPECT_LE(v.cwiseAbs().maxCoeff(), options.velocity_limits[0] * (1 + 1e-15));
  EXPECT_LT((limited.primary_jacobian() * v - 0.5 * limited.primary_velocity()).cwiseAbs().maxCoeff(), 1e-10);
}

gen::Description lola() { return scenario::lola_description(MBGEN_SOURCE_DIR); }
using scenario::lola_bent_pose;
using scenario::lola_tasks;

/// Lola's collision scene, pruned by 300 closed samples (its extras' exclusions honoured).
collision::CollisionModel lola_scene(const gen::Description& d) {
  gen::CollisionSceneOptions scene_options;
  scene_options.samples = 300;
  return gen::build_collision_scene(d, scene_options).model;
}

TEST(DifferentialIk, ClosedLoopsWorkInIndependentVelocities) {
  const gen::Description d = lola();
  const Model& model = d.model;
  ASSERT_FALSE(model.subsystems.empty());
  const collision::CollisionModel cm = lola_scene(d);
  DifferentialIkOptions options;
  options.collision_avoidance = true;
  options.collision = {0.08, 100.0};
  options.angular_momentum.enabled = true;
  DifferentialIk<double> ik(model, lola_tasks(), options, &cm);
  const VecX<double> q = lola_bent_pose(d);
  set_targets_near(ik, model, q, 11);
  ik.angular_momentum_target = Vec3<double>(0.5, 0.2, -0.3);
  VecX<double> v(model.nv());
  const StepReport report = ik.step(q, v);
  ASSERT_TRUE(report.ok);
  Data<double> data(model);
  closure_jacobian<double>(model, data, q);
  // Round-off scales with |J T| (T maps millimetres of actuator travel to radians: entries ~ 10)
  // times the velocity: the bounds are relative to that.
  const MatX<double> JT = ik.primary_jacobian() * ik.velocity_map();
  const double scale = JT.norm();
  const double primary = (ik.primary_jacobian() * v - ik.primary_velocity()).cwiseAbs().maxCoeff() /
                         std::max(1.0, scale * ik.coordinates_velocity().norm());
  const double closure = (data.Phi_q * v).cwiseAbs().maxCoeff();
  const VecX<double> secondary_full = ik.velocity_map() * ik.secondary_velocity();
  const double leak = (ik.primary_jacobian() * secondary_full).cwiseAbs().maxCoeff() / (scale * ik.secondary_velocity().norm());
  std::printf("  Lola (%d independent of %d velocities, %d of %zu pairs active, sigma_min %.3f, |J T| %.0f): |J v - xd| / |J T||c| %.1e, "
              "|Phi_q v| %.1e, |J v_secondary| / |J T||c_secondary| %.1e (|v_secondary| %.2f)\n",
              ik.num_coordinates(), model.nv(), report.active_pairs, cm.pairs.size(), report.smallest_singular_value, scale, primary,
              closure, leak, secondary_full.norm());
  ASSERT_GT(report.smallest_singular_value, 0.01);
  EXPECT_LT(ik.num_coordinates(), model.nv());
  EXPECT_LT(primary, 1e-12);  // 1.6e-13 seen: the products J (T c) and (J T) c round differently
  EXPECT_LT(closure, 1e-10);
  EXPECT_LT(leak, 1e-12);
  EXPECT_GT(secondary_full.norm(), 1e-3);  // the secondary objectives did something

  // Closed-loop kinematic simulation, 0.3 s at 1 kHz: integrate v, close the loops by Newton
  // (closure_positions) to remove the drift of first-order integration, step again.
  VecX<double> qk = q, next(model.nq());
  double worst_primary = 0, worst_closure = 0;
  for (int k = 0; k < 300; ++k) {
    ASSERT_TRUE(ik.step(qk, v).ok);
    worst_primary = std::max(worst_primary, (ik.primary_jacobian() * v - ik.primary_velocity()).cwiseAbs().maxCoeff() /
                                                (scale * ik.coordinates_velocity().norm()));
    closure_jacobian<double>(model, data, qk);
    worst_closure = std::max(worst_closure, (data.Phi_q * v).cwiseAbs().maxCoeff());
    integrate<double>(model, qk, v * 1e-3, next);
    qk = next;
    ASSERT_EQ(closure_positions<double>(model, data, qk).status, ClosureStatus::Converged);
  }
  std::printf("  Lola, 300 steps with loops re-closed: |J v - xd| / |J T||c| <= %.1e, |Phi_q v| <= %.1e\n", worst_primary,
              worst_closure);
  EXPECT_LT(worst_primary, 1e-12);
  EXPECT_LT(worst_closure, 1e-10);
}

TEST(DifferentialIk, SingularPoseGivesBoundedVelocities) {
  // The collision arm stretched along x, its link3 frame asked to go 1 m further out at 1 m/s:
  // the radial direction is lost (sigma = 0), the tangential ones are regular.
  const Model model = load_tree(MBGEN_TEST_DATA "/collision_arm.urdf", gen::BaseType::Fixed);
  DifferentialIk<double> ik(model, {{"reach", TaskKind::FramePosition, "link3", 1.0}});
  ik.target(0).position = Vec3<double>(1.9, 0.0, 0.0);
  VecX<double> q = VecX<double>::Zero(model.nq()), v(model.nv());
  const StepReport report = ik.step(q, v);
  ASSERT_TRUE(report.ok);
  EXPECT_TRUE(v.allFinite());
  EXPECT_LT(v.norm(), 1e-12);  // the only asked direction is the lost one: nothing to do
  // Slightly bent, with a tangential request as well. The default schedule (max_damping =
  // singular_region = 0.01) caps the gain sigma / (sigma^2 + lambda^2) at 1 / 0.01 along any
  // direction, so |v| <= 100 |xd|; the undamped inverse would give |v| ~ |xd| / sigma_min.
  for (double bend : {1e-2, 1e-4, 1e-8}) {
    q[1] = bend;
    ik.target(0).position = Vec3<double>(1.9, 0.5, 0.0);
    const StepReport bent = ik.step(q, v);
    ASSERT_TRUE(bent.ok);
    EXPECT_TRUE(v.allFinite());
    EXPECT_LE(v.norm(), 100.0 * ik.primary_velocity().norm() * (1 + 1e-12)) << "bend " << bend;
    std::printf("  stretched arm bent by %.0e rad: sigma_min %.1e, |v| / |xd| = %.2f\n", bend, bent.smallest_singular_value,
                v.norm() / ik.primary_velocity().norm());
  }
}

TEST(DifferentialIk, NonFiniteInputIsReportedNotCommanded) {
  const Model model = load_tree(MBGEN_TEST_DATA "/collision_arm.urdf", gen::BaseType::Fixed);
  DifferentialIk<double> ik(model, {{"tip", TaskKind::FramePosition, "link3", 5.0}});
  VecX<double> q(model.nq()), v = VecX<double>::Ones(model.nv());
  q << 0.0, 0.6, 2.0, 0.0;
  ik.target(0).position = Vec3<double>(std::nan(""), 0.0, 0.0);
  EXPECT_FALSE(ik.step(q, v).ok);
  EXPECT_EQ(v.cwiseAbs().maxCoeff(), 0.0);
  ik.target(0).position = Vec3<double>(0.35, 0.0, 0.0);
  q[1] = std::nan("");
  v.setOnes();
  EXPECT_FALSE(ik.step(q, v).ok);
  EXPECT_EQ(v.cwiseAbs().maxCoeff(), 0.0);
}

TEST(DifferentialIk, FloatScalarWorks) {
  const Model model = load_tree(MBGEN_TEST_DATA "/collision_arm.urdf", gen::BaseType::Fixed);
  DifferentialIk<float> ik(model, {{"tip", TaskKind::FramePosition, "link3", 5.0}});
  ik.target(0).position = Vec3<float>(0.35f, 0.0f, 0.0f);
  VecX<float> q(model.nq()), v(model.nv());
  q << 0.0f, 0.6f, 2.0f, 0.0f;
  ASSERT_TRUE(ik.step(q, v).ok);
  EXPECT_LT((ik.primary_jacobian() * v - ik.primary_velocity()).cwiseAbs().maxCoeff(), 1e-5f);
}

TEST(DifferentialIk, StepDoesNotAllocate) {
  const gen::Description d = lola();
  const collision::CollisionModel cm = lola_scene(d);
  DifferentialIkOptions options;
  options.collision_avoidance = true;
  options.angular_momentum.enabled = true;
  options.joint_limits.limits = joint_position_limits(d.model);
  DifferentialIk<double> ik(d.model, lola_tasks(), options, &cm);
  const VecX<double> q = lola_bent_pose(d);
  set_targets_near(ik, d.model, q, 12);
  const Model tree = talos();
  DifferentialIkOptions tree_options;
  tree_options.angular_momentum.enabled = true;
  tree_options.velocity_limits.assign(static_cast<std::size_t>(tree.nv()), 1.0);
  DifferentialIk<double> tree_ik(tree, talos_tasks(), tree_options);
  const VecX<double> tree_q = talos_pose(tree, 13);
  set_targets_near(tree_ik, tree, tree_q, 14);
  VecX<double> v(d.model.nv()), tree_v(tree.nv());
  {
    MallocGuard guard;
    ik.step(q, v);
    tree_ik.step(tree_q, tree_v);
    EXPECT_EQ(guard.count(), 0u);
  }
  EXPECT_TRUE(v.allFinite() && tree_v.allFinite());
}

template <typename F> std::string error_of(F&& make) {
  try {
    make();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no exception";
}

// The controller on the generated functions (BasicDifferentialIk<lola::Backend>: frame poses and
// Jacobians, CoM, centroidal momentum matrix, velocity map, the 178 pairs' distances) against
// the generic one over the same pairs: the same velocities to round-off along 200 steps of a
// kinematic simulation with every objective on, and no allocation in its step.
TEST(DifferentialIk, GeneratedBackendEqualsGeneric) {
  const gen::Description d = lola();
  const Model& model = d.model;
  const collision::CollisionModel cm = scenario::generated_collision_scene(d);
  ASSERT_EQ(static_cast<int>(cm.pairs.size()), lola::num_distance_pairs);
  for (int k = 0; k < lola::num_distance_pairs; ++k) {
    EXPECT_EQ(model.body(cm.compounds[static_cast<std::size_t>(cm.pairs[static_cast<std::size_t>(k)].first)].body).name,
              lola::distance_pair_names[k][0]);
    EXPECT_EQ(model.body(cm.compounds[static_cast<std::size_t>(cm.pairs[static_cast<std::size_t>(k)].second)].body).name,
              lola::distance_pair_names[k][1]);
  }
  const DifferentialIkOptions options = scenario::lola_ik_options();
  DifferentialIk<double> generic(model, lola_tasks(), options, &cm);
  BasicDifferentialIk<lola::Backend> generated(lola::Backend{}, lola_tasks(), options);
  ASSERT_EQ(generated.num_coordinates(), generic.num_coordinates());
  VecX<double> q = lola_bent_pose(d);
  set_targets_near(generic, model, q, 11);
  for (int i = 0; i < generic.num_tasks(); ++i) generated.target(i) = generic.target(i);
  generic.angular_momentum_target = generated.angular_momentum_target = Vec3<double>(0.5, 0.2, -0.3);
  VecX<double> v_generic(model.nv()), v_generated(model.nv()), next(model.nq());
  Data<double> data(model);
  double worst = 0;
  int active = 0;
  for (int k = 0; k < 200; ++k) {
    const StepReport a = generic.step(q, v_generic), b = generated.step(q, v_generated);
    ASSERT_TRUE(a.ok && b.ok) << k;
    EXPECT_EQ(a.active_pairs, b.active_pairs) << k;
    EXPECT_EQ(a.rank, b.rank) << k;
    active = std::max(active, a.active_pairs);
    worst = std::max(worst, (v_generated - v_generic).norm() / v_generic.norm());
    integrate<double>(model, q, v_generic * 1e-3, next);
    q = next;
    ASSERT_EQ(closure_positions<double>(model, data, q).status, ClosureStatus::Converged);
  }
  std::printf("  Lola, 200 steps: generated vs generic |v - v'| / |v| <= %.1e (%d of %d pairs active at most)\n", worst, active,
              lola::num_distance_pairs);
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(active, 0);  // the avoidance was exercised
  MallocGuard guard;
  generated.step(q, v_generated);
  EXPECT_EQ(guard.count(), 0u) << "generated-backend step allocated";
}

// The step computes rows for the near set only (the pairs within the activation distance; bounding
// spheres spare most far pairs' SSV calls); the collision gradient must be the one every pair gives. Along Lola's own motion, the
// step's dP/dq equals collision_potential_gradient over the full self_distances of the same
// backend, bit for bit on the generated one (the same rows, summed in the same order).
TEST(DifferentialIk, NearSetGivesTheFullSetsCollisionGradient) {
  const gen::Description d = lola();
  const Model& model = d.model;
  DifferentialIkOptions options = scenario::lola_ik_options();
  options.angular_momentum.enabled = false;
  BasicDifferentialIk<lola::Backend> ik(lola::Backend{}, lola_tasks(), options);
  VecX<double> q = lola_bent_pose(d);
  Data<double> data(model);
  {
    DifferentialIk<double> generic(model, lola_tasks());  // only to set the targets
    set_targets_near(generic, model, q, 11);
    for (int i = 0; i < generic.num_tasks(); ++i) ik.target(i) = generic.target(i);
  }
  const int np = lola::num_distance_pairs, nv = model.nv();
  std::vector<double> distance(np), normal(3 * np), witness(6 * np), J(np * nv);
  VecX<double> v(nv), next(model.nq()), full(nv);
  int most_near = 0, most_active = 0;
  for (int k = 0; k < 100; ++k) {
    const StepReport report = ik.step(q, v);
    ASSERT_TRUE(report.ok) << k;
    lola::self_distances(q.data(), distance.data(), normal.data(), witness.data(), J.data());
    const int active = collision_potential_gradient<double>(
        np, distance.data(), Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(J.data(), np, nv),
        options.collision, full);
    ASSERT_EQ(report.active_pairs, active) << k;
    ASSERT_EQ(report.near_pairs, active) << k;
    ASSERT_TRUE(ik.collision_gradient() == full) << k << ": " << (ik.collision_gradient() - full).norm();
    for (int p = 0; p < np; ++p) ASSERT_LE(ik.distances()[p], distance[p]) << "pair " << p;
    most_near = std::max(most_near, report.near_pairs);
    most_active = std::max(most_active, report.active_pairs);
    integrate<double>(model, q, v * 1e-3, next);
    q = next;
    ASSERT_EQ(closure_positions<double>(model, data, q).status, ClosureStatus::Converged);
  }
  std::printf("  Lola, 100 steps: at most %d near and %d active of %d pairs\n", most_near, most_active, np);
  EXPECT_GT(most_active, 0);
  EXPECT_LT(most_near, np / 3);  // the near set is what saves the work (45 of 178 within 8 cm)
}

// Joint limits (joint_limit_potential.hpp): the secondary velocity is the steepest descent of
// their potential within the primary tasks' null space, -N dP/dq (W = I, no other objective),
// checked against the KKT conditions of  min 1/2 |x + dP/dq|^2  s.t.  J x = 0.
TEST(DifferentialIk, JointLimitsDescendTheirPotentialInTheNullSpace) {
  const Model model = talos();
  VecX<double> q = talos_pose(model, 6);
  DifferentialIkOptions options;
  options.joint_limits.limits = joint_position_limits(model);
  options.joint_limits.activation = 0.15;
  int expected_active = 0;
  for (const JointLimit& l : options.joint_limits.limits)
    if (l.joint.rfind("arm_", 0) == 0) {  // the arms, which the primary tasks leave mostly free
      q[l.q_index] = (expected_active % 2 ? l.lower + 0.05 : l.upper + 0.02);
      ++expected_active;
    }
  for (const JointLimit& l : options.joint_limits.limits)
    if (l.joint.rfind("arm_", 0) != 0 && std::min(q[l.q_index] - l.lower, l.upper - q[l.q_index]) < 0.15) ++expected_active;
  DifferentialIk<double> ik(model, talos_tasks(), options);
  set_targets_near(ik, model, q, 7);
  VecX<double> v(model.nv());
  const StepReport report = ik.step(q, v);
  ASSERT_TRUE(report.ok);
  ASSERT_GT(report.smallest_singular_value, 0.01);  // no damping: N is the exact projector
  EXPECT_EQ(report.active_limits, expected_active);
  VecX<double> gradient = VecX<double>::Zero(model.nv());
  add_joint_limit_gradient<double>(q.data(), options.joint_limits, gradient);
  EXPECT_EQ((ik.collision_gradient() - gradient).norm(), 0.0);
  const MatX<double>& J = ik.primary_jacobian();
  const int n = model.nv(), m = static_cast<int>(J.rows());
  MatX<double> kkt = MatX<double>::Zero(n + m, n + m);
  kkt.topLeftCorner(n, n) = MatX<double>::Identity(n, n);
  kkt.topRightCorner(n, m) = J.transpose();
  kkt.bottomLeftCorner(m, n) = J;
  VecX<double> rhs = VecX<double>::Zero(n + m);
  rhs.head(n) = -gradient;
  const VecX<double> reference = kkt.fullPivLu().solve(rhs).head(n);
  const double error = (ik.secondary_velocity() - reference).norm() / reference.norm();
  std::printf("  talos, %d limits active: secondary vs KKT relative difference %.2e\n", report.active_limits, error);
  EXPECT_LT(error, 1e-10);
  EXPECT_LT(gradient.dot(ik.secondary_velocity()), 0.0);  // the potential decreases
  EXPECT_LT((J * v - ik.primary_velocity()).cwiseAbs().maxCoeff(), 1e-10);
}

// A joint beyond its limit is taken back inside while the tasks converge as without limits: talos'
// left elbow 0.05 rad past its upper limit, 1 s of kinematic simulation at 1 kHz from the same
// start to the same targets, with and without the limits.
TEST(DifferentialIk, JointLimitsTakeAJointBackInsideWhileTheTasksHold) {
  const Model model = talos();
  const std::vector<JointLimit> limits = joint_position_limits(model);
  const auto elbow = std::find_if(limits.begin(), limits.end(), [](const JointLimit& l) { return l.joint == "arm_left_4_joint"; });
  ASSERT_NE(elbow, limits.end());
  VecX<double> start = talos_pose(model, 8);
  start[elbow->q_index] = elbow->upper + 0.05;
  DifferentialIkOptions options;
  options.joint_limits.limits = limits;
  DifferentialIk<double> plain(model, talos_tasks()), limited(model, talos_tasks(), options);
  set_targets_near(plain, model, start, 9);
  for (int i = 0; i < plain.num_tasks(); ++i) {
    plain.target(i).velocity.setZero();  // fixed targets: the errors decay to zero
    limited.target(i) = plain.target(i);
  }
  const auto run = [&](DifferentialIk<double>& ik) {
    VecX<double> q = start, v(model.nv()), next(model.nq());
    double worst_rise = 0, potential = joint_limit_potential<double>(q.data(), options.joint_limits);
    for (int k = 0; k < 1000; ++k) {
      EXPECT_TRUE(ik.step(q, v).ok) << k;
      integrate<double>(model, q, v * 1e-3, next);
      q = next;
      const double p = joint_limit_potential<double>(q.data(), options.joint_limits);
      worst_rise = std::max(worst_rise, p - potential);
      potential = p;
    }
    ik.step(q, v);
    return std::make_pair(q, worst_rise);
  };
  const auto [q_plain, rise_plain] = run(plain);
  const auto [q_limited, rise_limited] = run(limited);
  (void)rise_plain;
  const double margin_plain = elbow->upper - q_plain[elbow->q_index], margin_limited = elbow->upper - q_limited[elbow->q_index];
  // Task errors at the end: what the desired velocity's feedback term sees (gain 10, so xd = 10 e).
  const double error_plain = plain.primary_velocity().cwiseAbs().maxCoeff() / 10.0;
  const double error_limited = limited.primary_velocity().cwiseAbs().maxCoeff() / 10.0;
  std::printf("  talos elbow: margin %.4f rad at the start, %.4f without limits, %.4f with; task error %.1e / %.1e; potential "
              "rose by at most %.1e per step\n",
              -0.05, margin_plain, margin_limited, error_plain, error_limited, rise_limited);
  EXPECT_LT(margin_plain, 0.0);                                   // nothing took it back
  EXPECT_GT(margin_limited, 0.9 * options.joint_limits.activation);  // back inside, out of the zone but for e^-10
  EXPECT_LE(rise_limited, 0.0);                                   // the potential never rose
  EXPECT_LT(error_plain, 1e-4);
  EXPECT_LT(error_limited, 1e-4);
  EXPECT_LT(std::abs(error_limited - error_plain), 1e-6);
}

// With loops the limits may sit on dependent joints (Lola's knee and ankle linkages): the gradient
// reaches the independent velocities through T^T, on the generated backend as on the generic one.
TEST(DifferentialIk, JointLimitsOnLoopJointsGoThroughTheVelocityMap) {
  const gen::Description d = lola();
  const Model& model = d.model;
  const VecX<double> q = lola_bent_pose(d);
  DifferentialIkOptions options;
  options.joint_limits.activation = 0.1;
  int dependent = 0;
  for (const SubSystem& sub : model.subsystems)
    for (int v : sub.dependent) {
      const Joint& joint = model.joint(model.joint_of_v(v));
      // a range whose lower limit is 0.04 rad below the pose: inside the margin
      options.joint_limits.limits.push_back({joint.name, joint.idx_q, joint.idx_v, q[joint.idx_q] - 0.04, q[joint.idx_q] + 1.0});
      ++dependent;
    }
  ASSERT_GT(dependent, 0);
  DifferentialIk<double> generic(model, lola_tasks(), options), plain(model, lola_tasks());
  BasicDifferentialIk<lola::Backend> generated(lola::Backend{}, lola_tasks(), options);
  set_targets_near(generic, model, q, 11);
  for (int i = 0; i < generic.num_tasks(); ++i) generated.target(i) = plain.target(i) = generic.target(i);
  VecX<double> v(model.nv()), v_generated(model.nv()), v_plain(model.nv());
  const StepReport a = generic.step(q, v), b = generated.step(q, v_generated);
  ASSERT_TRUE(a.ok && b.ok && plain.step(q, v_plain).ok);
  EXPECT_EQ(a.active_limits, dependent);
  EXPECT_EQ(b.active_limits, dependent);
  EXPECT_LT((v_generated - v).norm() / v.norm(), 1e-12);
  ASSERT_GT(a.smallest_singular_value, 0.01);  // no damping: the null space is exact
  VecX<double> gradient = VecX<double>::Zero(model.nv());
  add_joint_limit_gradient<double>(q.data(), options.joint_limits, gradient);
  // The secondary velocity (independent coordinates) against the KKT conditions of
  // min 1/2 |x + T^T dP/dq|^2  s.t.  J T x = 0, with T from the runtime's velocity_map.
  Data<double> data(model);
  const int nc = generic.num_coordinates();
  MatX<double> T(model.nv(), nc);
  velocity_map<double>(model, data, q, T);
  const MatX<double> A = generic.primary_jacobian() * T;
  const int m = static_cast<int>(A.rows());
  MatX<double> kkt = MatX<double>::Zero(nc + m, nc + m);
  kkt.topLeftCorner(nc, nc) = MatX<double>::Identity(nc, nc);
  kkt.topRightCorner(nc, m) = A.transpose();
  kkt.bottomLeftCorner(m, nc) = A;
  VecX<double> rhs = VecX<double>::Zero(nc + m);
  rhs.head(nc) = -T.transpose() * gradient;
  const VecX<double> reference = kkt.fullPivLu().solve(rhs).head(nc);
  const double error = (generic.secondary_velocity() - reference).norm() / reference.norm();
  // v = T c keeps the loops closed, and descends the potential faster than the plain step does.
  closure_jacobian<double>(model, data, q);
  EXPECT_LT((data.Phi_q * v).cwiseAbs().maxCoeff(), 1e-12 * v.norm());
  std::printf("  Lola, %d dependent joints in their margins: secondary vs KKT relative difference %.2e; dP/dt %.3e with limits, "
              "%.3e without\n",
              dependent, error, gradient.dot(v), gradient.dot(v_plain));
  EXPECT_LT(error, 1e-10);
  EXPECT_LT(gradient.dot(v), gradient.dot(v_plain));
  EXPECT_LT((generic.primary_jacobian() * v - generic.primary_velocity()).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(DifferentialIk, ConstructionErrorsSayWhatIsWrong) {
  const Model model = load_tree(MBGEN_TEST_DATA "/collision_arm.urdf", gen::BaseType::Fixed);
  EXPECT_EQ(error_of([&] { DifferentialIk<double>(model, {{"tip", TaskKind::FramePose, "nope", 1.0}}); }),
            "task 'tip': no frame named 'nope' in model 'collision_arm' (a URDF link or fixed joint name)");
  EXPECT_EQ(error_of([&] { DifferentialIk<double>(model, {}); }), "DifferentialIk: needs at least one primary task");
  EXPECT_EQ(error_of([&] { DifferentialIk<double>(model, {{"tip", TaskKind::FramePose, "link3", -1.0}}); }),
            "task 'tip': gain must be finite and >= 0, got -1.000000");
  DifferentialIkOptions options;
  options.weights = {1.0, 2.0};
  EXPECT_EQ(error_of([&] { DifferentialIk<double>(model, {{"tip", TaskKind::FramePose, "link3", 1.0}}, options); }),
            "DifferentialIk: weights has 2 entries, expected 4 (one per velocity coordinate, nv)");
  options.weights = {1.0, 2.0, 0.0, 1.0};
  EXPECT_EQ(error_of([&] { DifferentialIk<double>(model, {{"tip", TaskKind::FramePose, "link3", 1.0}}, options); }),
            "DifferentialIk: weights[2] = 0.000000 must be finite and > 0");
  options.weights.clear();
  options.collision_avoidance = true;
  EXPECT_EQ(error_of([&] { DifferentialIk<double>(model, {{"tip", TaskKind::FramePose, "link3", 1.0}}, options); }),
            "DifferentialIk: collision_avoidance needs a collision model (the scene's compounds and pairs)");
  EXPECT_EQ(error_of([&] {
              DifferentialIk<double>(model, {{"a", TaskKind::CenterOfMass, "", 1.0}, {"a", TaskKind::CenterOfMass, "", 1.0}});
            }),
            "DifferentialIk: two tasks named 'a'");
  {
    DifferentialIkOptions momentum;
    momentum.angular_momentum.enabled = true;
    momentum.angular_momentum.axis_weights = {1.0, -1.0, 1.0};
    EXPECT_EQ(error_of([&] { DifferentialIk<double>(model, {{"tip", TaskKind::FramePose, "link3", 1.0}}, momentum); }),
              "DifferentialIk: angular_momentum.axis_weights[1] = -1.000000 must be finite and >= 0");
  }
  {
    DifferentialIkOptions limits;
    limits.joint_limits.limits = joint_position_limits(model);
    ASSERT_FALSE(limits.joint_limits.limits.empty());
    limits.joint_limits.limits[0].q_index = model.nq();
    EXPECT_EQ(error_of([&] { DifferentialIk<double>(model, {{"tip", TaskKind::FramePose, "link3", 1.0}}, limits); }),
              "joint limits: '" + limits.joint_limits.limits[0].joint + "': coordinate q[" + std::to_string(model.nq()) + "], v[" +
                  std::to_string(limits.joint_limits.limits[0].v_index) + "] outside the model's nq = " + std::to_string(model.nq()) +
                  ", nv = " + std::to_string(model.nv()));
  }
  // On a backend: a task frame must be one of its frames (a generated backend's: the scene's
  // `jacobians:`); the generic backend refuses a name the model does not have.
  EXPECT_EQ(error_of([&] { BasicDifferentialIk<lola::Backend>(lola::Backend{}, {{"hand", TaskKind::FramePosition, "forearm_l", 1.0}}); }),
            "task 'hand': frame 'forearm_l' is not among the backend's frames (foot_l, foot_r, torso): generate it (the scene's "
            "`jacobians:`)");
  EXPECT_EQ(error_of([&] { sim::GenericBackend<double>(model).set_frames({"link3", "nope"}); }),
            "backend: no frame named 'nope' in model 'collision_arm' (a URDF link or fixed joint name)");
  const gen::Description d = lola();
  options.collision_avoidance = false;
  options.weights.assign(static_cast<std::size_t>(d.model.nv()), 1.0);
  const std::string loops = error_of([&] { DifferentialIk<double>(d.model, lola_tasks(), options); });
  EXPECT_NE(loops.find("(one per independent velocity: the model has closed loops)"), std::string::npos) << loops;
}

}  // namespace
}  // namespace mbgen::test
