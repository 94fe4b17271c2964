// Position, velocity and acceleration maps of closed loops (runtime/include/mbgen/algorithm/
// closure_positions.hpp, subsystem_maps.hpp): Phi_q T = 0 and Phi_q (T ydd + g) = gamma on every
// closed-loop description, Newton and the maps against the closed forms of
// robots/mechanisms/README.md (four-bar: Freudenstein; slider-crank), the dead point of a
// slider-driven slider-crank, and no allocation per call.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <random>

#include "malloc_guard.hpp"
#include "mbgen/sim/backend.hpp"
#include "mbgen/sim/simulator.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

const std::string kMechanisms = MBGEN_SOURCE_DIR "/robots/mechanisms/";

gen::Description load(const std::string& urdf, const std::string& extras) {
  gen::LoadOptions options;
  options.extras_file = extras;
  return gen::load_description(urdf, options);
}

int q_index(const Model& model, const std::string& joint) { return model.joint(*model.find_joint(joint)).idx_q; }

/// T (nv x ny) at q.
MatX<double> velocity_map_at(const Model& model, Data<double>& data, const VecX<double>& q) {
  MatX<double> T(model.nv(), static_cast<int>(model.structure().independent_v.size()));
  velocity_map<double>(model, data, q, T);
  return T;
}

std::vector<int> dependent_coordinates(const Model& model) {
  std::vector<int> z;
  for (const SubSystem& s : model.subsystems) z.insert(z.end(), s.dependent.begin(), s.dependent.end());
  return z;
}

class LoopMapsTest : public ::testing::TestWithParam<LoopCase> {
 protected:
  LoopMapsTest() : d(load_loop_case(GetParam())), model(d.model), data(model) {}
  gen::Description d;
  const Model& model;
  Data<double> data;
};

TEST_P(LoopMapsTest, IndependentCoordinatesCountTheClosedDof) {
  EXPECT_EQ(static_cast<int>(model.structure().independent_v.size()), d.closed_dof);
  EXPECT_EQ(static_cast<int>(model.structure().independent_v.size() + dependent_coordinates(model).size()), model.nv());
}

TEST_P(LoopMapsTest, VelocityMapIsInTheNullSpaceOfTheConstraints) {
  // Phi_q G = 0 on all rows (redundant ones too: they are consistent on the closed set);
  // 1e-10 relative to |Phi_q| |G|, round-off of solving with Phi_z (condition up to ~1e3 here).
  std::mt19937_64 rng(21);
  for (int trial = 0; trial < 3; ++trial) {
    VecX<double> q, v;
    ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
    const MatX<double> T = velocity_map_at(model, data, q);
    const MatX<double> Phi_q = closure_jacobian<double>(model, data, q);
    EXPECT_LT((Phi_q * T).norm(), 1e-10 * Phi_q.norm() * T.norm());
    // T is the identity on the independent coordinates.
    for (std::size_t i = 0; i < model.structure().independent_v.size(); ++i) EXPECT_EQ(T(model.structure().independent_v[i], i), 1.0);
    // full_velocities is T vy without forming T (the same products: 1e-15 relative).
    const VecX<double> vy = random_vector<double>(static_cast<int>(model.structure().independent_v.size()), rng);
    VecX<double> v_full(model.nv());
    full_velocities<double>(model, data, q, vy, v_full);
    EXPECT_LT(relative_error(v_full, VecX<double>(T * vy)), 1e-15);
  }
}

TEST_P(LoopMapsTest, AccelerationBiasSatisfiesTheAccelerationConstraint) {
  // qdd = G ydd + g keeps Phi_q qdd = gamma for any ydd: on all rows, to 1e-9 relative.
  std::mt19937_64 rng(22);
  VecX<double> q, v;
  ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
  const MatX<double> T = velocity_map_at(model, data, q);
  VecX<double> vy(static_cast<int>(model.structure().independent_v.size())), g(model.nv());
  for (int i = 0; i < vy.size(); ++i) vy[i] = v[model.structure().independent_v[static_cast<std::size_t>(i)]];
  acceleration_bias<double>(model, data, q, vy, g);
  const VecX<double> gamma = closure_bias<double>(model, data, q, v);
  const MatX<double> Phi_q = closure_jacobian<double>(model, data, q);
  const VecX<double> ydd = random_vector<double>(static_cast<int>(model.structure().independent_v.size()), rng);
  EXPECT_LT(relative_error(Phi_q * (T * ydd + g), gamma), 1e-9);
}

TEST_P(LoopMapsTest, NewtonRecoversTheDependentCoordinates) {
  // Move z off a closed pose; Newton from there returns to it (same branch) to 1e-10.
  std::mt19937_64 rng(23);
  VecX<double> q, v;
  ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
  VecX<double> moved = q;
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int z : dependent_coordinates(model)) moved[model.q_index_of_v(z)] += 1e-3 * unit(rng);
  const ClosureResult<double> result = closure_positions<double>(model, data, moved);
  ASSERT_EQ(result.status, ClosureStatus::Converged);
  EXPECT_LT((moved - q).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LE(result.iterations, 6);
  EXPECT_LT(result.residual, 1e-12);
  EXPECT_GT(result.pivot_ratio, 1e-5);
}

TEST_P(LoopMapsTest, NewtonReadsNoPoseItDidNotPlace) {
  // closure_positions places only the cycles' bodies (ModelStructure::cycle_bodies): a body it missed would
  // be read as the last pass left it. From the same start, a fresh Data and one whose every pose
  // is another configuration's must give the same iterates, bit for bit.
  std::mt19937_64 rng(29);
  VecX<double> q, v;
  ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int z : dependent_coordinates(model)) q[model.q_index_of_v(z)] += 1e-3 * unit(rng);
  Data<double> stale(model);
  forward_kinematics<double>(model, stale, random_configuration<double>(model, rng));
  VecX<double> fresh_q = q, stale_q = q;
  const ClosureResult<double> fresh_result = closure_positions<double>(model, data, fresh_q);
  const ClosureResult<double> stale_result = closure_positions<double>(model, stale, stale_q);
  ASSERT_EQ(fresh_result.status, ClosureStatus::Converged);
  EXPECT_EQ(stale_result.status, fresh_result.status);
  EXPECT_EQ(stale_result.iterations, fresh_result.iterations);
  EXPECT_EQ(stale_q, fresh_q);
}

TEST_P(LoopMapsTest, MapsReadNoPoseTheyDidNotPlace) {
  // The sub-systems' maps place only the cycles' bodies too: T and g at a consistent state must be
  // the same bits from a fresh Data and from one whose every pose is another configuration's.
  std::mt19937_64 rng(31);
  VecX<double> q, v;
  ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
  VecX<double> vy(static_cast<int>(model.structure().independent_v.size()));
  for (std::size_t i = 0; i < model.structure().independent_v.size(); ++i) vy[static_cast<int>(i)] = v[model.structure().independent_v[i]];
  Data<double> stale(model);
  forward_kinematics<double>(model, stale, random_configuration<double>(model, rng));
  VecX<double> g_fresh(model.nv()), g_stale(model.nv());
  acceleration_bias<double>(model, data, q, vy, g_fresh);
  acceleration_bias<double>(model, stale, q, vy, g_stale);
  EXPECT_EQ(g_stale, g_fresh);
  forward_kinematics<double>(model, stale, random_configuration<double>(model, rng));
  EXPECT_EQ(velocity_map_at(model, stale, q), velocity_map_at(model, data, q));
}

TEST_P(LoopMapsTest, CloseLoopsProjectsTheVelocitiesAsFullVelocitiesDoes) {
  // close_loops from a moved pose and an inconsistent v: q closed as closure_positions closes it
  // (within 1e-10: closure_positions may end with a simplified step, close_loops never does), and
  // v's dependent entries those of full_velocities at close_loops' q (its independent ones kept), to
  // 1e-13 relative; an unconverged closure leaves v alone.
  std::mt19937_64 rng(31);
  VecX<double> q, v;
  ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  VecX<double> moved = q, v_moved = v;
  for (int z : dependent_coordinates(model)) moved[model.q_index_of_v(z)] += 1e-3 * unit(rng), v_moved[z] += unit(rng);
  VecX<double> q_closed = moved, q_both = moved, v_both = v_moved;
  const ClosureResult<double> expected = closure_positions<double>(model, data, q_closed);
  const ClosureResult<double> result = close_loops<double>(model, data, q_both, v_both);
  ASSERT_EQ(result.status, ClosureStatus::Converged);
  EXPECT_LE(std::abs(result.iterations - expected.iterations), 1);
  EXPECT_LT((q_both - q_closed).cwiseAbs().maxCoeff(), 1e-10);
  VecX<double> vy(static_cast<int>(model.structure().independent_v.size())), v_expected(model.nv());
  for (int i = 0; i < vy.size(); ++i) vy[i] = v_moved[model.structure().independent_v[static_cast<std::size_t>(i)]];
  full_velocities<double>(model, data, q_both, vy, v_expected);
  EXPECT_LT((v_both - v_expected).cwiseAbs().maxCoeff(), 1e-13 * v_expected.cwiseAbs().maxCoeff());
  EXPECT_GT((v_moved - v_expected).cwiseAbs().maxCoeff(), 1e-3) << "the projection did something";
  VecX<double> nan_q = moved, untouched = v_moved;
  nan_q[model.q_index_of_v(dependent_coordinates(model).front())] = std::nan("");
  EXPECT_EQ(close_loops<double>(model, data, nan_q, untouched).status, ClosureStatus::NotConverged);
  EXPECT_EQ(untouched, v_moved);
}

/// The generated code's float settings (closure_options_float): a float Newton's tolerances.
ClosureOptions float_options() { return default_closure_options<float>(); }

TEST_P(LoopMapsTest, ResidualCheckAndSimplifiedStepCloseAsNewtonDoes) {
  // closure_positions checks an iterate that quadratic convergence predicts closed by its residual
  // alone, and when that is not yet below the tolerance takes one simplified step with the last
  // factor (detail::residual_check_predicted); close_loops always takes full Newton steps. Both
  // must close the loops: the same status, closure_positions' reported residual the kept residual
  // recomputed at its q and below the tolerance, q within 1e-10 of close_loops' (two poses closed
  // to 1e-12, kappa(Phi_z) apart at most), at most one step more. Its pivot ratios are the factor's
  // one or two steps before q, within 1e-3 relative of close_loops' at these regular poses. From
  // warm starts 1e-3 off, both the check and the simplified step must fire on some draws: counted,
  // and required for the loop robots whose Newton takes three steps (cassie_like, digit_like_2legs).
  std::mt19937_64 rng(37);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int draws = 0, checked_by_residual = 0, simplified = 0, three_steps = 0;
  for (int trial = 0; trial < 64 && draws < 16; ++trial) {
    VecX<double> q, v;
    if (!consistent_state(model, d.assembly.q, rng, 0.05, q, v)) continue;
    ++draws;
    VecX<double> moved = q;
    for (int z : dependent_coordinates(model)) moved[model.q_index_of_v(z)] += 1e-3 * unit(rng);
    VecX<double> q_positions = moved, q_both = moved, v_both = v;
    const ClosureResult<double> positions = closure_positions<double>(model, data, q_positions);
    const ClosureResult<double> both = close_loops<double>(model, data, q_both, v_both);
    ASSERT_EQ(positions.status, ClosureStatus::Converged);
    ASSERT_EQ(both.status, ClosureStatus::Converged);
    double recomputed = 0;
    closure_residual<double>(model, data, q_positions);
    ASSERT_TRUE(detail::kept_residual<double>(model, data, recomputed));
    EXPECT_EQ(positions.residual, recomputed);
    EXPECT_LT(positions.residual, ClosureOptions{}.tolerance);
    EXPECT_LT((q_positions - q_both).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_LE(positions.iterations, both.iterations + 1);
    EXPECT_LT(std::abs(positions.pivot_ratio - both.pivot_ratio), 1e-3 * both.pivot_ratio);
    if (positions.pivot_ratio != both.pivot_ratio) ++checked_by_residual;
    if (q_positions != q_both) ++simplified;  // the same steps would have given the same bits
    if (both.iterations >= 3) ++three_steps;
  }
  ASSERT_GT(draws, 0);
  if (three_steps > 0) {
    EXPECT_GT(checked_by_residual, 0) << "no iterate was checked by its residual alone";
    EXPECT_GT(simplified, 0) << "no simplified step was taken";
  }
  RecordProperty("checked_by_residual", std::to_string(checked_by_residual) + " of " + std::to_string(draws));
  std::printf("  %s: %d of %d draws checked by their residual, %d closed through a simplified step (%d took three Newton steps)\n",
              model.name.c_str(), checked_by_residual, draws, simplified, three_steps);
}

TEST_P(LoopMapsTest, PredictedStartIsCheckedByItsResidualAfterOneNewtonStep) {
  // From where a simulator's step leaves q, q (+) h v with h = 1 ms (every coordinate moved by its
  // velocity: the loops open by O(h^2)), the step's own size predicts its result
  // (detail::residual_check_predicted: r |step|^2 below the tolerance), so the first Newton
  // step's iterate is checked by its residual alone (then, if needed, one simplified step) instead
  // of by a second Newton step: closure_positions then reports the first factor's pivot ratio
  // where close_loops, which always takes full steps, reports its last one's. Required on every
  // draw that needs a step (all but the couplings'); on 1 of 16 draws of the ill-conditioned
  // wl16_like (kappa(Phi_z) ~ 6e3), 1 ms of its velocities leaves Newton's basin and both report
  // not converged. Both close the loops to the tolerance, q within 1e-10 of each other.
  std::mt19937_64 rng(53);
  int needed_a_step = 0, checked = 0;
  for (int trial = 0; trial < 16; ++trial) {
    VecX<double> q, v;
    ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
    VecX<double> start(model.nq());
    integrate<double>(model, q, 1e-3 * v, start);
    VecX<double> q_positions = start, q_both = start, v_both = v;
    const ClosureResult<double> positions = closure_positions<double>(model, data, q_positions);
    const ClosureResult<double> both = close_loops<double>(model, data, q_both, v_both);
    ASSERT_EQ(positions.status, both.status);
    if (both.status != ClosureStatus::Converged) continue;
    EXPECT_LT(positions.residual, ClosureOptions{}.tolerance);
    EXPECT_LT((q_positions - q_both).cwiseAbs().maxCoeff(), 1e-10);
    if (both.iterations == 0) continue;
    ++needed_a_step;
    if (positions.pivot_ratio != both.pivot_ratio) ++checked;
  }
  std::printf("  %s: %d of 16 predicted starts needed a Newton step, %d of them closed by a residual check\n",
              GetParam().name.c_str(), needed_a_step, checked);
  EXPECT_EQ(checked, needed_a_step);
  // Couplings are linear in q: a predicted start is closed already.
  const bool only_couplings = std::all_of(model.closures.begin(), model.closures.end(),
                                          [](const LoopClosure& c) { return c.type == ClosureType::Coupling; });
  if (!only_couplings) {
    EXPECT_GT(needed_a_step, 0);
  }
}

TEST_P(LoopMapsTest, SimulatorStepLeavesItsProjectionOneNewtonStep) {
  // What the simulator's projection (close_loops after every step, to its closure_tolerance,
  // 1e-11) is handed: from consistent states (independent velocities up to 1 rad/s or m/s), one
  // step of the default integrator (RK4, 1e-4 s; no contact, no controller) drifts the loops by
  // less than that tolerance on at least half of the states of every model (all of them but on
  // wl16_like, whose ill-conditioned loops drift up to ~2e-10 on 2 of the 8), so close_loops
  // closes at its first Newton step (0 iterations), the step the velocities need anyway; and a
  // second step always suffices. In a simulation, closing the loops costs one Newton step per
  // step, two at most (bench project/<robot>, docs/loops.md). An integrator that moved the
  // loops apart, or a velocity map off the constraint, drifts them by ~1e-4 of the velocity error.
  std::mt19937_64 rng(47);
  sim::SimulatorOptions options;
  options.project = false;
  options.contact = false;
  // The random states lie around the assembled pose, some past a joint's range: a stop's push
  // there (Cassie's assembled pose is outside nine ranges) is a stiff force of its own, not the
  // drift of a smooth step this test measures.
  options.joint_stops.enabled = false;
  double worst_drift = 0;
  int within = 0;
  const int states = 8;
  for (int state = 0; state < states; ++state) {
    VecX<double> q, v;
    ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
    sim::Simulator<sim::GenericBackend<double>> simulator(sim::GenericBackend<double>(model), options);
    ASSERT_EQ(simulator.set_state(q.data(), v.data()), 0);
    ASSERT_EQ(simulator.step(), sim::StepStatus::ok);
    VecX<double> stepped_q = simulator.q(), stepped_v = simulator.v();
    double drift = 0;
    closure_residual<double>(model, data, stepped_q);
    ASSERT_TRUE(detail::kept_residual<double>(model, data, drift));
    worst_drift = std::max(worst_drift, drift);
    if (drift < options.closure_tolerance) ++within;
    ClosureOptions projection;
    projection.tolerance = options.closure_tolerance;
    const ClosureResult<double> result = close_loops<double>(model, data, stepped_q, stepped_v, projection);
    EXPECT_EQ(result.status, ClosureStatus::Converged) << state;
    EXPECT_EQ(result.iterations, drift < options.closure_tolerance ? 0 : 1) << state << ": drift " << drift;
  }
  EXPECT_GE(2 * within, states) << within << " of " << states << " steps drifted less than the projection's tolerance";
  std::printf("  %s: %d of %d steps within the projection's tolerance, largest drift %.1e\n", model.name.c_str(), within, states,
              worst_drift);
}

TEST_P(LoopMapsTest, NewtonOnRegularPosesIsConvergedInDoubleAndFloat) {
  // No false dead point: from seeded random closed poses (spread 0.05, as test_generated) with
  // the dependent coordinates moved by up to 1e-3, Newton reports converged, in double with the
  // defaults and in float with the generated float settings. The figures behind
  // dead_point_tolerance (2e-2 in float): the smallest relative pivot ratio met here.
  std::mt19937_64 rng(25);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Data<float> data_f(model);
  double smallest[2] = {1, 1}, smallest_ratio[2] = {1, 1};
  for (int trial = 0; trial < 8; ++trial) {
    VecX<double> q, v;
    ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
    VecX<double> moved = q;
    for (int z : dependent_coordinates(model)) moved[model.q_index_of_v(z)] += 1e-3 * unit(rng);
    VecX<double> closed = moved;
    const ClosureResult<double> in_double = closure_positions<double>(model, data, closed);
    EXPECT_EQ(in_double.status, ClosureStatus::Converged) << trial << ": relative pivot ratio " << in_double.relative_pivot_ratio;
    VecX<float> closed_f = moved.cast<float>();
    const ClosureResult<float> in_float = closure_positions<float>(model, data_f, closed_f, float_options());
    EXPECT_EQ(in_float.status, ClosureStatus::Converged) << trial << ": " << to_string(in_float.status) << ", residual "
                                                         << in_float.residual << ", pivot ratio " << in_float.pivot_ratio
                                                         << ", relative " << in_float.relative_pivot_ratio;
    smallest[0] = std::min(smallest[0], in_double.relative_pivot_ratio);
    smallest[1] = std::min(smallest[1], static_cast<double>(in_float.relative_pivot_ratio));
    smallest_ratio[0] = std::min(smallest_ratio[0], in_double.pivot_ratio);
    smallest_ratio[1] = std::min(smallest_ratio[1], static_cast<double>(in_float.pivot_ratio));
  }
  std::cout << "[ pivots   ] " << GetParam().name << ": smallest pivot ratio double " << smallest_ratio[0] << ", float "
            << smallest_ratio[1] << "; relative to the assembled pose: double " << smallest[0] << ", float " << smallest[1] << "\n";
}

TEST_P(LoopMapsTest, MapsDoNotAllocate) {
  std::mt19937_64 rng(24);
  VecX<double> q, v;
  ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
  MatX<double> T(model.nv(), static_cast<int>(model.structure().independent_v.size()));
  VecX<double> vy = VecX<double>::Ones(T.cols()), v_full(model.nv()), g(model.nv());
  ClosureStatus status;
  {
    MallocGuard guard;
    status = closure_positions<double>(model, data, q).status;
    velocity_map<double>(model, data, q, T);
    full_velocities<double>(model, data, q, vy, v_full);
    acceleration_bias<double>(model, data, q, vy, g);
    closure_residual<double>(model, data, q);
    EXPECT_EQ(guard.count(), 0u);
  }
  EXPECT_EQ(status, ClosureStatus::Converged);
}

TEST_P(LoopMapsTest, NanStateIsNotConvergedNeverConverged) {
  // A NaN in a coordinate of a loop (held or warm start): a status, not a "closed" pose.
  VecX<double> q = d.assembly.q;
  q[model.q_index_of_v(model.subsystems.front().coordinates.front())] = std::nan("");
  const ClosureResult<double> result = closure_positions<double>(model, data, q);
  EXPECT_NE(result.status, ClosureStatus::Converged);
  EXPECT_EQ(result.iterations, 0);
}

TEST_P(LoopMapsTest, NonFiniteCoordinateOffTheLoopsIsNotConverged) {
  // The rows read only the loops' own coordinates (closure.hpp), so a NaN or an infinity in a
  // coordinate off the loops (a floating base's, a hip's above a knee loop) would not reach them:
  // closure_positions checks those itself. Not converged at once, no sub-system to blame, q left
  // as it was. (A NaN on a loop is Newton's to find: NanStateIsNotConvergedNeverConverged.)
  int off_loop = -1;
  for (int k = 1; k < model.num_bodies() && off_loop < 0; ++k)
    if (model.structure().subsystem_of_body[BodyIndex(k)] < 0) off_loop = model.joint(model.body(BodyIndex(k)).joint).idx_q;
  if (off_loop < 0) GTEST_SKIP() << "every joint is on a loop";
  for (const double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    VecX<double> q = d.assembly.q;
    q[off_loop] = bad;
    const VecX<double> given = q;
    const ClosureResult<double> result = closure_positions<double>(model, data, q);
    EXPECT_EQ(result.status, ClosureStatus::NotConverged);
    EXPECT_EQ(result.iterations, 0);
    EXPECT_TRUE(std::isnan(result.residual));
    EXPECT_EQ(result.subsystem, -1);
    for (int i = 0; i < q.size(); ++i)
      if (i != off_loop) {
        EXPECT_EQ(q[i], given[i]);
      }
    VecX<double> v = VecX<double>::Zero(model.nv());
    EXPECT_EQ(close_loops<double>(model, data, q, v).status, ClosureStatus::NotConverged);
  }
}

INSTANTIATE_TEST_SUITE_P(ClosedLoops, LoopMapsTest, ::testing::ValuesIn(loop_cases()),
                         [](const auto& info) { return info.param.name; });

TEST(ModelCoordinates, QIndexOfVPairsOneDofJointsOnly) {
  // Lola: a floating base (q 0..6, v 0..5), then 1-DoF joints with q index = v index + 1.
  const gen::Description d = load(MBGEN_SOURCE_DIR "/robots/lola/lola.urdf", MBGEN_SOURCE_DIR "/robots/lola/lola.yaml");
  const Model& model = d.model;
  for (int v = 0; v < 6; ++v) {
    EXPECT_EQ(model.q_index_of_v(v), -1) << v;
    EXPECT_EQ(model.joint_of_v(v).value(), 1) << v;
  }
  for (int j = 2; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    EXPECT_EQ(model.joint_of_v(joint.idx_v).value(), j);
    EXPECT_EQ(model.q_index_of_v(joint.idx_v), joint.idx_q);
    EXPECT_EQ(joint.idx_q, joint.idx_v + 1);
  }
  EXPECT_EQ(model.q_index_of_v(model.nv()), -1);  // out of range
  EXPECT_EQ(model.q_index_of_v(-1), -1);
}

// ---- closed forms (robots/mechanisms/README.md) -------------------------------------------

/// Four-bar (Freudenstein): rocker angle theta4 for crank angle theta2, the nominal branch.
double freudenstein_theta4(double theta2) {
  const double a = 0.05, b = 0.182, c = 0.122, d = 0.19;
  const double K1 = d / a, K2 = d / c, K3 = (a * a - b * b + c * c + d * d) / (2 * a * c);
  const double A = std::cos(theta2) - K1 - K2 * std::cos(theta2) + K3, B = -2 * std::sin(theta2);
  const double C = K1 - (K2 + 1) * std::cos(theta2) + K3;
  return 2 * std::atan2(-B - std::sqrt(B * B - 4 * A * C), 2 * A);
}

TEST(LoopMapsClosedForm, FourBarFollowsFreudenstein) {
  // The crank turns a full revolution in 0.05 rad steps, Newton warm-started from the last pose;
  // the rocker matches the closed form to 1e-10 rad, and the rocker rate from G matches the
  // closed form's derivative (central differences, h = 1e-6: 1e-8).
  const gen::Description d = load(kMechanisms + "four_bar.urdf", kMechanisms + "four_bar.yaml");
  const Model& model = d.model;
  Data<double> data(model);
  ASSERT_EQ(model.structure().independent_v, std::vector<int>{model.joint(*model.find_joint("crank_joint")).idx_v});
  const int crank = q_index(model, "crank_joint"), rocker = q_index(model, "rocker_joint");
  const int coupler = q_index(model, "coupler_joint");
  const double theta20 = M_PI / 2, theta40 = std::atan2(0.12, -0.022), theta30 = std::atan2(0.07, 0.168);
  VecX<double> q = VecX<double>::Zero(model.nq());
  double worst_angle = 0, worst_rate = 0;
  for (int step = 1; step <= 126; ++step) {
    q[crank] = 0.05 * step;
    ASSERT_EQ(closure_positions<double>(model, data, q).status, ClosureStatus::Converged) << step;
    const double theta2 = theta20 + q[crank];
    const double rocker_expected = std::remainder(freudenstein_theta4(theta2) - theta40, 2 * M_PI);
    worst_angle = std::max(worst_angle, std::abs(std::remainder(q[rocker] - rocker_expected, 2 * M_PI)));
    // Coupler: b (cos t3, sin t3) = d (1, 0) + c (cos t4, sin t4) - a (cos t2, sin t2).
    const double t4 = theta40 + q[rocker];
    const double t3 = std::atan2(0.122 * std::sin(t4) - 0.05 * std::sin(theta2), 0.19 + 0.122 * std::cos(t4) - 0.05 * std::cos(theta2));
    worst_angle = std::max(worst_angle, std::abs(std::remainder(q[coupler] - (t3 - theta30 - q[crank]), 2 * M_PI)));
    const MatX<double> T = velocity_map_at(model, data, q);
    const double h = 1e-6;
    const double rate = std::remainder(freudenstein_theta4(theta2 + h) - freudenstein_theta4(theta2 - h), 2 * M_PI) / (2 * h);
    worst_rate = std::max(worst_rate, std::abs(T(model.joint(*model.find_joint("rocker_joint")).idx_v, 0) - rate));
  }
  EXPECT_LT(worst_angle, 1e-10);
  EXPECT_LT(worst_rate, 1e-8);
}

TEST(LoopMapsClosedForm, SliderCrankFollowsItsClosedForm) {
  // x(theta) = r cos theta + sqrt(l^2 - r^2 sin^2 theta), slider_joint = x - 0.12, and
  // xdot = -r thetadot [sin theta + r sin theta cos theta / sqrt(l^2 - r^2 sin^2 theta)].
  const gen::Description d = load(kMechanisms + "slider_crank.urdf", kMechanisms + "slider_crank.yaml");
  const Model& model = d.model;
  Data<double> data(model);
  const int crank = q_index(model, "crank_joint"), slider = q_index(model, "slider_joint");
  const int slider_v = model.joint(*model.find_joint("slider_joint")).idx_v;
  const double r = 0.05, l = 0.13;
  VecX<double> q = VecX<double>::Zero(model.nq());
  for (int step = 1; step <= 126; ++step) {
    q[crank] = 0.05 * step;
    ASSERT_EQ(closure_positions<double>(model, data, q).status, ClosureStatus::Converged) << step;
    const double theta = M_PI / 2 + q[crank], root = std::sqrt(l * l - r * r * std::sin(theta) * std::sin(theta));
    EXPECT_NEAR(q[slider], r * std::cos(theta) + root - 0.12, 1e-12) << step;
    EXPECT_NEAR(velocity_map_at(model, data, q)(slider_v, 0), -r * (std::sin(theta) + r * std::sin(theta) * std::cos(theta) / root), 1e-12) << step;
  }
}

/// tests/data/mechanisms/slider_crank_slider_driven.yaml: the slider is independent. At the
/// stroke end x = l + r (slider_joint = 0.06) crank and rod are in line and Phi_z is singular;
/// beyond it there is no closed pose. Either way: a status, and a finite q. Returns the result at
/// the stroke end.
template <typename S> ClosureResult<S> approach_the_stroke_end(const ClosureOptions& options) {
  const gen::Description d = load(kMechanisms + "slider_crank.urdf", MBGEN_TEST_DATA "/mechanisms/slider_crank_slider_driven.yaml");
  const Model& model = d.model;
  Data<S> data(model);
  const int slider = q_index(model, "slider_joint");
  EXPECT_EQ(model.structure().independent_v, std::vector<int>{model.joint(*model.find_joint("slider_joint")).idx_v});
  VecX<S> q = VecX<S>::Zero(model.nq());
  // Warm-started approach: regular until close to the stroke end.
  for (double x : {0.01, 0.02, 0.03, 0.04, 0.05}) {
    q[slider] = S(x);
    const ClosureResult<S> r = closure_positions<S>(model, data, q, options);
    EXPECT_EQ(r.status, ClosureStatus::Converged) << x << ": relative pivot ratio " << r.relative_pivot_ratio;
  }
  q[slider] = S(0.06);
  const ClosureResult<S> at_dead_point = closure_positions<S>(model, data, q, options);
  EXPECT_EQ(at_dead_point.status, ClosureStatus::Singular) << to_string(at_dead_point.status) << ", residual " << at_dead_point.residual
                                                           << ", relative pivot ratio " << at_dead_point.relative_pivot_ratio;
  EXPECT_TRUE(q.allFinite());
  const VecX<S> at_stroke_end = q;
  q[slider] = S(0.07);  // beyond the stroke
  const ClosureResult<S> beyond = closure_positions<S>(model, data, q, options);
  EXPECT_NE(beyond.status, ClosureStatus::Converged);
  EXPECT_TRUE(q.allFinite());
  std::cout << "[ dead pt  ] " << (sizeof(S) == 8 ? "double" : "float") << " at the stroke end: " << to_string(at_dead_point.status)
            << " after " << at_dead_point.iterations << " steps (pivot ratio " << at_dead_point.pivot_ratio << ", relative "
            << at_dead_point.relative_pivot_ratio << ", residual " << at_dead_point.residual << "); beyond: " << to_string(beyond.status)
            << " (residual " << beyond.residual << ")\n";
  return at_dead_point;
}

TEST(LoopMapsDeadPoint, SliderDrivenToTheStrokeEndIsSingularNotNaN) {
  // double: the pivot ratio itself falls below singular_tolerance (1e-5) on the way in, before
  // the residual reaches 1e-12: the dead-point test at convergence plays no part, and without it
  // (dead_point_tolerance 0, the rule before it) the same status comes in the same steps (18).
  const ClosureResult<double> at_dead_point = approach_the_stroke_end<double>(ClosureOptions{});
  EXPECT_LT(at_dead_point.pivot_ratio, 1e-5);
  ClosureOptions pivot_test_only;
  pivot_test_only.dead_point_tolerance = 0;
  const ClosureResult<double> before = approach_the_stroke_end<double>(pivot_test_only);
  EXPECT_EQ(at_dead_point.iterations, before.iterations);
  EXPECT_EQ(at_dead_point.iterations, 18);
}

TEST(LoopMapsDeadPoint, FloatNewtonTellsTheStrokeEndByTheRelativePivotRatio) {
  // float: Newton closes the loop to 2e-6 while still ~2e-3 in pivot ratio from the dead point
  // (above singular_tolerance, 1e-3); relative to the assembled pose's ratio (0.42) that is
  // ~4.5e-3, below dead_point_tolerance (2e-2): singular, not converged.
  const ClosureResult<float> at_dead_point = approach_the_stroke_end<float>(float_options());
  EXPECT_GE(at_dead_point.pivot_ratio, 1e-3f);  // what the relative test adds: the plain one passes here
  EXPECT_LT(at_dead_point.relative_pivot_ratio, 2e-2f);
}

}  // namespace
}  // namespace mbgen::test
