// The QP form of the differential IK (differential_ik.hpp, QpStepOptions; dense_qp.hpp), checked
// against what it claims:
//  - with no inequality binding, it is the potential form's step (the same objective, 1e-12);
//  - scripted motions push a joint into its stop (TALOS' arms, driven by momentum tracking) and one
//    leg against the other (Lola's right foot released and pulled inward): every limit and the
//    smallest distance hold at every step while the primary tasks are achieved exactly (1e-12),
//    and the same motions without the inequalities go past them (the tests can fail);
//  - when the inequalities forbid the tasks, the step relaxes them, the inequalities still hold,
//    and the heavier task gives less;
//  - the last step's active rows start the next QP (no active-set change when nothing changed);
//  - generated backend equals generic (1e-10 along a scripted motion), no allocation in step(),
//    construction errors by their text.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "collision/collision_scene.hpp"
#include "lola.hpp"
#include "lola_ik_scenario.hpp"
#include "malloc_guard.hpp"
#include "mbgen/control/differential_ik.hpp"
#include "model/load_description.hpp"
#include "talos_ik_scenario.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

using namespace mbgen::control;
using scenario::set_targets_near;
using scenario::talos_pose;
using scenario::lola_bent_pose;
using scenario::lola_tasks;
using scenario::talos_tasks;

Model talos() { return load_tree(shared_robot("talos/talos_reduced.urdf"), gen::BaseType::Floating); }
gen::Description lola() { return scenario::lola_description(MBGEN_SOURCE_DIR); }

/// The smallest margin of q to the limits (negative: past one).
double smallest_margin(const VecX<double>& q, const std::vector<JointLimit>& limits) {
  double m = 1e9;
  for (const JointLimit& l : limits) m = std::min({m, q[l.q_index] - l.lower, l.upper - q[l.q_index]});
  return m;
}

/// q with every limited coordinate moved at least `inset` inside its range (talos_pose draws
/// joints in [-0.2, 0.2] rad, outside some of TALOS' ranges).
VecX<double> inside(VecX<double> q, const std::vector<JointLimit>& limits, double inset = 0.02) {
  for (const JointLimit& l : limits) q[l.q_index] = std::clamp(q[l.q_index], l.lower + inset, l.upper - inset);
  return q;
}

/// Every task's target where the generated kinematics put its frame (or the CoM) at q, at rest.
void hold_targets_at(BasicDifferentialIk<lola::Backend>& ik, const VecX<double>& q) {
  std::vector<double> X(12 * lola::num_frames), J(6 * lola::nv * lola::num_frames), com(3), Ag(6 * lola::nv);
  lola::Backend{}.task_kinematics(q.data(), X.data(), J.data(), com.data(), Ag.data());
  for (int i = 0; i < ik.num_tasks(); ++i) {
    const Task& t = ik.task(i);
    ik.target(i).velocity.setZero();
    if (t.spec.kind == TaskKind::CenterOfMass) {
      ik.target(i).position = Vec3<double>(com[0], com[1], com[2]);
      continue;
    }
    const double* x = X.data() + 12 * t.slot;
    ik.target(i).position = Vec3<double>(x[3], x[7], x[11]);
    ik.target(i).rotation << x[0], x[1], x[2], x[4], x[5], x[6], x[8], x[9], x[10];
  }
}

/// |J v - xd| relative to |J| |v| (the null-space property's measure).
template <typename Ik> double primary_residual(const Ik& ik, const VecX<double>& v) {
  return (ik.primary_jacobian() * v - ik.primary_velocity()).cwiseAbs().maxCoeff() / std::max(1.0, ik.primary_jacobian().norm() * v.norm());
}

TEST(DifferentialIkQp, WithNothingBindingItIsThePotentialFormsStep) {
  const gen::Description d = lola();
  const collision::CollisionModel cm = scenario::generated_collision_scene(d);
  DifferentialIkOptions options = scenario::lola_ik_options();
  DifferentialIkOptions qp_options = options;
  qp_options.qp.enabled = true;
  qp_options.qp.min_distance = 0.0;
  DifferentialIk<double> potential(d.model, lola_tasks(), options, &cm), qp(d.model, lola_tasks(), qp_options, &cm);
  const VecX<double> q = lola_bent_pose(d);
  set_targets_near(potential, d.model, q, 21);
  for (int i = 0; i < potential.num_tasks(); ++i) qp.target(i) = potential.target(i);
  potential.angular_momentum_target = qp.angular_momentum_target = Vec3<double>(0.5, 0.2, -0.3);
  VecX<double> v(d.model.nv()), v_qp(d.model.nv());
  const StepReport a = potential.step(q, v), b = qp.step(q, v_qp);
  ASSERT_TRUE(a.ok && b.ok);
  EXPECT_EQ(b.qp_status, QpStatus::solved);
  EXPECT_FALSE(b.tasks_relaxed);
  EXPECT_GT(b.inequalities, 0);  // the near pairs' rows were there, none binding
  EXPECT_EQ(b.active_inequalities, 0);
  EXPECT_GT(a.active_pairs, 0);  // the collision descent is part of both objectives
  const double difference = (v_qp - v).norm() / v.norm();
  std::printf("  Lola: QP form vs potential form, nothing binding: |v - v'| / |v| = %.1e (%d rows)\n", difference, b.inequalities);
  EXPECT_LT(difference, 1e-12);
}

// TALOS' feet, CoM and torso held while momentum tracking asks for a large yaw momentum: the arms
// swing into their stops. With the QP form every limit holds at every step (a tree's coordinates
// integrate exactly: q + dt v, so the velocity damper's bound holds on q itself) and the tasks are
// exact; the potential form without limits takes the arms past them.
TEST(DifferentialIkQp, AJointPushedIntoItsStopStaysInsideWhileTheTasksHold) {
  const Model model = talos();
  const std::vector<JointLimit> limits = joint_position_limits(model);
  DifferentialIkOptions free_options;
  free_options.angular_momentum = {true, 1e4, {0.0, 0.0, 1.0}};
  DifferentialIkOptions qp_options = free_options;
  qp_options.qp.enabled = true;
  qp_options.joint_limits.limits = limits;
  qp_options.joint_limits.activation = 0.1;
  const auto run = [&](const DifferentialIkOptions& options, double& worst_margin, double& worst_residual, int& relaxed, int& active) {
    DifferentialIk<double> ik(model, talos_tasks(), options);
    VecX<double> q = inside(talos_pose(model, 3), limits, 0.06), v(model.nv()), next(model.nq());
    set_targets_near(ik, model, q, 4);
    for (int i = 0; i < ik.num_tasks(); ++i) ik.target(i).velocity.setZero();
    worst_margin = smallest_margin(q, limits), worst_residual = 0, relaxed = 0, active = 0;
    for (int k = 0; k < 1500; ++k) {
      ik.angular_momentum_target = Vec3<double>(0, 0, 8.0 * std::sin(2 * M_PI * k * 1e-3));
      const StepReport r = ik.step(q, v);
      EXPECT_TRUE(r.ok) << k << ": " << to_string(r.qp_status);
      relaxed += r.tasks_relaxed ? 1 : 0;
      active = std::max(active, r.active_inequalities);
      worst_residual = std::max(worst_residual, primary_residual(ik, v));
      integrate<double>(model, q, v * 1e-3, next);
      q = next;
      worst_margin = std::min(worst_margin, smallest_margin(q, limits));
    }
  };
  double margin_free, residual_free, margin_qp, residual_qp;
  int relaxed_free, relaxed_qp, active_free, active_qp;
  run(free_options, margin_free, residual_free, relaxed_free, active_free);
  run(qp_options, margin_qp, residual_qp, relaxed_qp, active_qp);
  std::printf("  TALOS, 1.5 s of yaw-momentum tracking: smallest joint margin %.4f rad without limits, %.2e with the QP form (%d "
              "inequalities active at most, %d steps relaxed); |J v - xd| <= %.1e\n",
              margin_free, margin_qp, active_qp, relaxed_qp, residual_qp);
  // limit_margin keeps that much of every range free (its rows switch on within the activation).
  DifferentialIkOptions kept = qp_options;
  kept.qp.limit_margin = 0.05;
  double margin_kept, residual_kept;
  int relaxed_kept, active_kept;
  run(kept, margin_kept, residual_kept, relaxed_kept, active_kept);
  std::printf("  the same with limit_margin 0.05: smallest joint margin %.4f rad\n", margin_kept);
  EXPECT_GE(margin_kept, 0.05 - 1e-12);
  EXPECT_LT(margin_kept, 0.06);  // and it is reached: the margin, not the range, did the stopping
  EXPECT_LT(margin_free, -0.05);   // the motion does push past a stop
  EXPECT_GE(margin_qp, -1e-12);    // every stop held
  EXPECT_GT(active_qp, 0);
  EXPECT_EQ(relaxed_qp, 0);        // the arms' limits never forbid the tasks
  EXPECT_LT(residual_qp, 1e-12);   // the tasks exact at every step
}

// The warm start across steps: the step's rows are renumbered as limits and pairs come and go,
// and the last step's active rows, found again by what they are, start the next QP. The same
// state stepped twice: the second QP starts at its optimum's active set (no active-set change),
// a fresh controller at the same state adds those rows one by one, and both give the same step.
TEST(DifferentialIkQp, TheLastStepsActiveRowsStartTheNextQp) {
  const Model model = talos();
  const std::vector<JointLimit> limits = joint_position_limits(model);
  DifferentialIkOptions options;
  options.angular_momentum = {true, 1e4, {0.0, 0.0, 1.0}};
  options.qp.enabled = true;
  options.joint_limits.limits = limits;
  options.joint_limits.activation = 0.1;
  DifferentialIk<double> ik(model, talos_tasks(), options);
  VecX<double> q = inside(talos_pose(model, 3), limits, 0.06), v(model.nv()), next(model.nq());
  set_targets_near(ik, model, q, 4);
  for (int i = 0; i < ik.num_tasks(); ++i) ik.target(i).velocity.setZero();
  // Into the stops (as AJointPushedIntoItsStopStaysInsideWhileTheTasksHold) until rows bind.
  StepReport r;
  int k = 0;
  for (; k < 1500; ++k) {
    ik.angular_momentum_target = Vec3<double>(0, 0, 8.0 * std::sin(2 * M_PI * k * 1e-3));
    r = ik.step(q, v);
    ASSERT_TRUE(r.ok) << k;
    if (r.active_inequalities >= 3) break;
    integrate<double>(model, q, v * 1e-3, next);
    q = next;
  }
  ASSERT_GE(r.active_inequalities, 3) << "the motion never made three rows bind";
  VecX<double> again(model.nv()), fresh_v(model.nv());
  const StepReport repeated = ik.step(q, again);
  DifferentialIk<double> fresh(model, talos_tasks(), options);
  for (int i = 0; i < ik.num_tasks(); ++i) fresh.target(i) = ik.target(i);
  fresh.angular_momentum_target = ik.angular_momentum_target;
  const StepReport cold = fresh.step(q, fresh_v);
  ASSERT_TRUE(repeated.ok && cold.ok);
  std::printf("  TALOS at step %d, %d of %d rows active: QP active-set changes %d repeated (warm), %d fresh (cold); |v - v'| / |v| = %.1e\n",
              k, repeated.active_inequalities, repeated.inequalities, repeated.qp_iterations, cold.qp_iterations,
              (again - fresh_v).norm() / fresh_v.norm());
  EXPECT_EQ(repeated.active_inequalities, r.active_inequalities);
  EXPECT_EQ(repeated.qp_iterations, 0);
  EXPECT_GE(cold.qp_iterations, cold.active_inequalities);
  EXPECT_EQ(cold.active_inequalities, repeated.active_inequalities);
  EXPECT_LT((again - fresh_v).norm(), 1e-10 * fresh_v.norm());  // another order of the same rows: round-off (1.3e-12 seen)
  EXPECT_LT((again - v).norm(), 1e-10 * v.norm());
}

// QpStepOptions::smoothing. Lola stands, its tasks held; at step 200 the right foot's rows are
// released and softly pulled inward at 0.2 m/s (released_weight 100): the null-space optimum
// changes at once, and without smoothing so does the commanded velocity, in one step. With
// smoothing 1000 the step closes about 1 / (1 + 1000 / 100) of the gap per step: the jump is
// several times smaller and the velocity reaches the new optimum over a few steps, no change
// between two steps as large as the unsmoothed jump; the held tasks stay exact. The first step
// after restart() is pulled toward rest, as the first step of all is.
TEST(DifferentialIkQp, SmoothingSpreadsAJumpOfTheOptimumOverSteps) {
  const gen::Description d = lola();
  const Model& model = d.model;
  struct Result {
    double jump = 0, later = 0, worst_residual = 0, after_restart = 0, without_restart = 0;
    int relaxed = 0;
  };
  const auto run = [&](double smoothing) {
    DifferentialIkOptions options;
    options.qp.enabled = true;
    options.qp.released_weight = 100.0;
    options.qp.smoothing = smoothing;
    BasicDifferentialIk<lola::Backend> ik(lola::Backend{}, lola_tasks(), options);
    VecX<double> q = lola_bent_pose(d), v(model.nv()), last = VecX<double>::Zero(model.nv()), next(model.nq());
    hold_targets_at(ik, q);
    const int right = ik.task_index("right_foot");
    Result r;
    for (int k = 0; k < 400; ++k) {
      if (k == 200) {
        ik.target(right).released.fill(true);
        ik.target(right).velocity[1] = 0.2;
      }
      if (k == 300) {
        BasicDifferentialIk<lola::Backend> kept = ik;  // the step this one would be without restart()
        VecX<double> probe(model.nv());
        EXPECT_TRUE(kept.step(q, probe).ok);
        r.without_restart = probe.norm();
        ik.restart();
      }
      const StepReport report = ik.step(q, v);
      EXPECT_TRUE(report.ok) << k;
      r.relaxed += report.tasks_relaxed ? 1 : 0;
      if (k == 200) r.jump = (v - last).norm();
      if (k > 200 && k != 300) r.later = std::max(r.later, (v - last).norm());
      if (k == 300) r.after_restart = v.norm();
      r.worst_residual = std::max(r.worst_residual, primary_residual(ik, v));
      last = v;
      integrate<double>(model, q, v * 1e-3, next);
      q = next;
      EXPECT_EQ(lola::Backend{}.closure_positions(q.data()), 0) << k;
    }
    return r;
  };
  const Result sharp = run(0.0), smooth = run(1000.0);
  std::printf("  Lola, a foot released at step 200: velocity change in that step %.3f without smoothing, %.3f with 1000 (the largest "
              "after it %.3f); after restart() %.3f (without it %.3f)\n",
              sharp.jump, smooth.jump, smooth.later, smooth.after_restart, smooth.without_restart);
  EXPECT_GT(sharp.jump, 0.05);  // the release does move the optimum
  EXPECT_LT(smooth.jump, 0.25 * sharp.jump);
  EXPECT_LT(smooth.later, 0.25 * sharp.jump);
  EXPECT_LT(smooth.after_restart, 0.5 * smooth.without_restart);
  for (const Result& r : {sharp, smooth}) {
    EXPECT_LT(r.worst_residual, 1e-12);
    EXPECT_EQ(r.relaxed, 0);
  }
}

// Lola's right foot released in every direction and pulled, softly, toward the left foot's side:
// the legs close in until the distance inequality stops them (5 mm), the other tasks exact.
TEST(DifferentialIkQp, TwoLegsPushedTogetherStayApart) {
  const gen::Description d = lola();
  const Model& model = d.model;
  std::vector<int> leg_pairs;
  for (int p = 0; p < lola::num_distance_pairs; ++p) {
    const std::string a = lola::distance_pair_names[p][0], b = lola::distance_pair_names[p][1];
    const bool left_a = a.back() == 'l' && a[a.size() - 2] == '_', right_b = b.back() == 'r' && b[b.size() - 2] == '_';
    const bool right_a = a.back() == 'r' && a[a.size() - 2] == '_', left_b = b.back() == 'l' && b[b.size() - 2] == '_';
    if ((left_a && right_b) || (right_a && left_b)) leg_pairs.push_back(p);
  }
  ASSERT_GT(leg_pairs.size(), 10u);
  const double min_distance = 0.005;
  const auto run = [&](bool qp, double& closest, double& worst_residual, int& relaxed) {
    DifferentialIkOptions options;
    options.collision_avoidance = qp;
    options.collision = {0.05, 100.0};
    options.qp.enabled = true;
    options.qp.min_distance = min_distance;
    options.qp.released_weight = 100.0;
    BasicDifferentialIk<lola::Backend> ik(lola::Backend{}, lola_tasks(), options);
    lola::Backend backend;
    VecX<double> q = lola_bent_pose(d), v(model.nv()), next(model.nq());
    hold_targets_at(ik, q);
    const int right = ik.task_index("right_foot");
    ik.target(right).released.fill(true);
    ik.target(right).velocity[1] = 0.2;  // toward the left foot (+y), softly
    std::vector<double> distance(lola::num_distance_pairs), normal(3 * distance.size()), witness(6 * distance.size()),
        distance_J(distance.size() * model.nv());
    closest = 1e9, worst_residual = 0, relaxed = 0;
    for (int k = 0; k < 600; ++k) {
      ik.target(right).position.y() += 0.2e-3;
      const StepReport r = ik.step(q, v);
      EXPECT_TRUE(r.ok) << k;
      relaxed += r.tasks_relaxed ? 1 : 0;
      worst_residual = std::max(worst_residual, primary_residual(ik, v));
      integrate<double>(model, q, v * 1e-3, next);
      q = next;
      EXPECT_EQ(backend.closure_positions(q.data()), 0) << k;
      backend.self_distances(q.data(), distance.data(), normal.data(), witness.data(), distance_J.data());
      for (int p : leg_pairs) closest = std::min(closest, distance[static_cast<std::size_t>(p)]);
    }
  };
  double closest_free, residual_free, closest_qp, residual_qp;
  int relaxed_free, relaxed_qp;
  run(false, closest_free, residual_free, relaxed_free);
  run(true, closest_qp, residual_qp, relaxed_qp);
  std::printf("  Lola, the right leg pulled inward for 0.6 s: legs %.1f mm apart at the closest without the distance inequality, "
              "%.2f mm with it (bound %.1f); |J v - xd| <= %.1e, %d steps relaxed\n",
              1e3 * closest_free, 1e3 * closest_qp, 1e3 * min_distance, residual_qp, relaxed_qp);
  EXPECT_LT(closest_free, 0.0);                      // pulled through each other without it
  EXPECT_GE(closest_qp, min_distance - 2e-4);         // first order at 1 kHz: a distance's curvature
  EXPECT_LT(closest_qp, min_distance + 1e-3);         // the inequality did the stopping
  EXPECT_EQ(relaxed_qp, 0);
  EXPECT_LT(residual_qp, 1e-12);
}

// TALOS with every joint's range cut to 2 mrad around its pose: only the floating base can move,
// and the 18 task rows cannot all hold. The step relaxes them; every limit holds; the feet
// (weight 100) give less than the torso (weight 1).
TEST(DifferentialIkQp, ForbiddenTasksAreRelaxedAndTheHeavierGivesLess) {
  const Model model = talos();
  std::vector<JointLimit> limits = joint_position_limits(model);
  const VecX<double> q = inside(talos_pose(model, 5), limits);
  for (JointLimit& l : limits) l.lower = q[l.q_index] - 1e-3, l.upper = q[l.q_index] + 1e-3;  // every joint nearly locked
  std::vector<TaskSpec> tasks = talos_tasks();
  for (TaskSpec& t : tasks) t.weight = t.name == "torso" ? 1.0 : 100.0;
  DifferentialIkOptions options;
  options.qp.enabled = true;
  options.joint_limits.limits = limits;
  DifferentialIk<double> ik(model, tasks, options);
  set_targets_near(ik, model, q, 6);
  for (int i = 0; i < ik.num_tasks(); ++i) ik.target(i).velocity.setZero();
  ik.target(ik.task_index("right_foot")).position.z() += 0.1;
  VecX<double> v(model.nv()), next(model.nq());
  const StepReport r = ik.step(q, v);
  ASSERT_TRUE(r.ok) << to_string(r.qp_status);
  EXPECT_TRUE(r.tasks_relaxed);
  integrate<double>(model, q, v * 1e-3, next);
  EXPECT_GE(smallest_margin(next, limits), -1e-12);
  const VecX<double> residual = ik.primary_jacobian() * v - ik.primary_velocity();
  const Task& foot = ik.task(ik.task_index("right_foot"));
  const Task& torso = ik.task(ik.task_index("torso"));
  const double foot_error = residual.segment(foot.row, foot.rows()).norm() / ik.primary_velocity().segment(foot.row, foot.rows()).norm();
  const double torso_error = residual.segment(torso.row, torso.rows()).norm() /
                             std::max(1e-9, ik.primary_velocity().segment(torso.row, torso.rows()).norm());
  std::printf("  TALOS, every joint locked, right foot asked up: relaxed, %d inequalities active; relative task error foot %.2e, torso %.2e\n",
              r.active_inequalities, foot_error, torso_error);
  EXPECT_GT(r.active_inequalities, 0);
  EXPECT_LT(foot_error, torso_error);
}

TEST(DifferentialIkQp, GeneratedBackendEqualsGenericAndDoesNotAllocate) {
  const gen::Description d = lola();
  const Model& model = d.model;
  const collision::CollisionModel cm = scenario::generated_collision_scene(d);
  DifferentialIkOptions options = scenario::lola_ik_options();
  options.qp.enabled = true;
  options.qp.min_distance = 0.015;  // the arms start 20 mm from the body: rows bind as they swing
  options.collision.activation_distance = 0.05;
  options.joint_limits.limits = joint_position_limits(model);
  options.velocity_limits.assign(static_cast<std::size_t>(lola::ny), 3.0);
  DifferentialIk<double> generic(model, lola_tasks(), options, &cm);
  BasicDifferentialIk<lola::Backend> generated(lola::Backend{}, lola_tasks(), options);
  VecX<double> q = lola_bent_pose(d);
  set_targets_near(generic, model, q, 11);
  for (int i = 0; i < generic.num_tasks(); ++i) generated.target(i) = generic.target(i);
  generic.angular_momentum_target = generated.angular_momentum_target = Vec3<double>(0.5, 0.2, -0.3);
  VecX<double> v_generic(model.nv()), v_generated(model.nv()), next(model.nq());
  double worst = 0;
  int active = 0;
  for (int k = 0; k < 100; ++k) {
    const StepReport a = generic.step(q, v_generic), b = generated.step(q, v_generated);
    ASSERT_TRUE(a.ok && b.ok) << k << ": " << to_string(a.qp_status) << ", " << to_string(b.qp_status);
    EXPECT_EQ(a.active_inequalities, b.active_inequalities) << k;
    active = std::max(active, a.active_inequalities);
    worst = std::max(worst, (v_generated - v_generic).norm() / v_generic.norm());
    integrate<double>(model, q, v_generic * 1e-3, next);
    q = next;
    ASSERT_EQ(lola::Backend{}.closure_positions(q.data()), 0);
  }
  std::printf("  Lola QP form, 100 steps: generated vs generic |v - v'| / |v| <= %.1e, %d inequalities active at most\n", worst, active);
  EXPECT_LT(worst, 1e-10);
  EXPECT_GT(active, 0);
  std::size_t allocations = 0;
  {
    const MallocGuard guard;
    generated.step(q, v_generated);
    generic.step(q, v_generic);
    allocations = guard.count();
  }
  EXPECT_EQ(allocations, 0u);
}

TEST(DifferentialIkQp, ConstructionErrorsSayWhatIsWrong) {
  const Model model = talos();
  const auto error = [&](const DifferentialIkOptions& options, std::vector<TaskSpec> tasks = talos_tasks()) {
    try {
      DifferentialIk<double> ik(model, tasks, options);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  DifferentialIkOptions o;
  o.qp.enabled = true;
  o.qp.limit_horizon = 0;
  EXPECT_NE(error(o).find("limit_horizon"), std::string::npos) << error(o);
  o.qp.limit_horizon = 0.05;
  o.joint_limits.limits = joint_position_limits(model);
  o.qp.limit_margin = 0.2;  // beyond the activation margin 0.1: a limit would get its row too late
  EXPECT_NE(error(o).find("limit_margin"), std::string::npos) << error(o);
  o.qp.limit_margin = 0.0;
  o.qp.smoothing = -1;
  EXPECT_NE(error(o).find("qp.smoothing must be finite and >= 0, got -1"), std::string::npos) << error(o);
  o.qp.smoothing = 0;
  std::vector<TaskSpec> tasks = talos_tasks();
  tasks[2].weight = -1;
  EXPECT_NE(error(o, tasks).find("task 'com': weight"), std::string::npos) << error(o, tasks);
  EXPECT_EQ(error(o), "no exception");
}

}  // namespace
}  // namespace mbgen::test
