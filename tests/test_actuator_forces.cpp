// The closed system's inverse dynamics for the actuators (runtime algorithm/actuator_forces.hpp,
// generator model/actuated_coordinates.cpp). The independent check is forward dynamics: the
// actuators' forces plus the residual, applied as joint forces, must give back the accelerations
// they were computed for (normwise backward error 1e-12), on every closed-loop description the loop tests use, on
// floating-base Lola (the residual is the base's six), and for an actuator that is a dependent
// coordinate of its loop (the slider of the crank-driven slider-crank), whose force also meets
// the crank's by virtual power. Then the refusals, and the dead point.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "load/load_error.hpp"
#include "model/actuated_coordinates.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

/// Independent accelerations of the closed system under joint forces tau (nv).
VecX<double> independent_accelerations(const Model& model, Data<double>& data, const VecX<double>& q, const VecX<double>& vy,
                                       const VecX<double>& tau) {
  VecX<double> ydd(static_cast<int>(model.structure().independent_v.size()));
  if (model.subsystems.empty()) {
    VecX<double> v = vy;
    ydd = aba<double>(model, data, q, v, tau);
    return ydd;
  }
  forward_dynamics_loops_independent<double>(model, data, q, vy, tau);
  for (int i = 0; i < ydd.size(); ++i) ydd[i] = data.ddq[model.structure().independent_v[static_cast<std::size_t>(i)]];
  return ydd;
}

/// Joint forces (nv) of the actuators' forces f and the residual r (placed at the independent
/// coordinates, whose rows of T are those of the identity).
VecX<double> joint_forces(const Model& model, const Actuation& act, const VecX<double>& f, const VecX<double>& r) {
  VecX<double> tau = VecX<double>::Zero(model.nv());
  for (int i = 0; i < act.num_actuators(); ++i) tau[act.actuated_v[static_cast<std::size_t>(i)]] += f[i];
  for (int i = 0; i < r.size(); ++i) tau[model.structure().independent_v[static_cast<std::size_t>(i)]] += r[i];
  return tau;
}

VecX<double> independent_of(const Model& model, const VecX<double>& v) {
  VecX<double> vy(static_cast<int>(model.structure().independent_v.size()));
  for (int i = 0; i < vy.size(); ++i) vy[i] = v[model.structure().independent_v[static_cast<std::size_t>(i)]];
  return vy;
}

/// Worst relative error of forward dynamics with the actuators' forces against ydd, over
/// `states` consistent states of d.
double worst_round_trip(const gen::Description& d, const Actuation& act, int states, unsigned seed) {
  const Model& model = d.model;
  Data<double> data(model);
  std::mt19937_64 rng(seed);
  double worst = 0;
  int done = 0;
  for (int attempt = 0; attempt < 4 * states && done < states; ++attempt) {
    VecX<double> q, v;
    if (!consistent_state(model, d.assembly.q, rng, 0.05, q, v)) continue;
    ++done;
    const VecX<double> vy = independent_of(model, v);
    const VecX<double> ydd = random_vector<double>(vy.size(), rng, 5.0);
    VecX<double> f(act.num_actuators()), r(vy.size());
    EXPECT_TRUE(actuator_forces<double>(model, data, act, q, vy, ydd, f, r));
    const VecX<double> back = independent_accelerations(model, data, q, vy, joint_forces(model, act, f, r));
    // Normwise backward error: M_y (ydd' - ydd) against the terms of the equation, which the
    // conditioning of M_y does not amplify (wl16_like's forward error reaches 1e-11..1e-10).
    const MatX<double> My = mass_matrix_loops<double>(model, data, q);
    worst = std::max(worst, (My * (back - ydd)).norm() / (My.norm() * ydd.norm() + f.norm() + r.norm()));
  }
  EXPECT_EQ(done, states) << "consistent states drawn";
  return worst;
}

class ActuatorForcesOnLoops : public ::testing::TestWithParam<LoopCase> {};

TEST_P(ActuatorForcesOnLoops, GiveBackTheAccelerations) {
  const gen::Description d = load_loop_case(GetParam());
  const Actuation act = gen::description_actuation(d);
  const double worst = worst_round_trip(d, act, 10, 7);
  EXPECT_LT(worst, 1e-12);
  std::printf("  %s: %d actuator(s), forward dynamics of their forces vs ydd: backward error %.1e\n", GetParam().name.c_str(), act.num_actuators(), worst);
}

INSTANTIATE_TEST_SUITE_P(Loops, ActuatorForcesOnLoops, ::testing::ValuesIn(loop_cases()),
                         [](const ::testing::TestParamInfo<LoopCase>& info) { return info.param.name; });

TEST(ActuatorForces, LolaTheResidualIsTheFloatingBase) {
  const gen::Description d = load_lola();
  const Actuation act = gen::description_actuation(d);
  ASSERT_EQ(act.num_actuators(), 24);  // every joint of `independent:`, the knee and ankle actuators among them
  ASSERT_TRUE(act.blocks.empty());
  EXPECT_LT(worst_round_trip(d, act, 10, 11), 1e-12);
  // The residual: the base's six entries, the rest exactly zero; standing still in gravity, the
  // base's force is the weight (the whole robot's, world z along the base's z at the assembled pose).
  Data<double> data(d.model);
  const int ny = static_cast<int>(d.model.structure().independent_v.size());
  VecX<double> f(24), r(ny);
  VecX<double> q = d.assembly.q;
  const VecX<double> zero = VecX<double>::Zero(ny);
  ASSERT_TRUE(actuator_forces<double>(d.model, data, act, q, zero, zero, f, r));
  for (int i = 6; i < ny; ++i) EXPECT_EQ(r[i], 0.0) << i;
  const double weight = d.model.total_mass() * 9.81;
  EXPECT_NEAR(r.head<3>().norm(), weight, 1e-9 * weight);
}

/// The crank-driven slider-crank with the slider as the actuator: a dependent coordinate.
struct SliderCrank {
  gen::Description d = [] {
    gen::LoadOptions options;
    options.extras_file = MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.yaml";
    return gen::load_description(MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.urdf", options);
  }();
  int crank = d.model.joint(*d.model.find_joint("crank_joint")).idx_v;
  int slider = d.model.joint(*d.model.find_joint("slider_joint")).idx_v;
};

TEST(ActuatorForces, ADependentActuatorIsSolvedThroughItsLoop) {
  SliderCrank sc;
  const Model& model = sc.d.model;
  Data<double> data(model);
  ASSERT_EQ(model.structure().column_of_v[static_cast<std::size_t>(sc.slider)], -1) << "the slider must be dependent here";
  const Actuation by_slider = make_actuation(model, {sc.slider});
  const Actuation by_crank = make_actuation(model, {sc.crank});
  ASSERT_EQ(by_slider.blocks.size(), 1u);
  EXPECT_LT(worst_round_trip(sc.d, by_slider, 20, 3), 1e-12);
  // Virtual power: the slider's force times its speed is the crank's torque times its rate.
  std::mt19937_64 rng(5);
  for (int k = 0; k < 20; ++k) {
    VecX<double> q, v;
    ASSERT_TRUE(consistent_state(model, sc.d.assembly.q, rng, 0.5, q, v));
    const VecX<double> vy = independent_of(model, v), ydd = random_vector<double>(vy.size(), rng, 5.0);
    VecX<double> f_slider(1), f_crank(1), r(vy.size());
    ASSERT_TRUE(actuator_forces<double>(model, data, by_slider, q, vy, ydd, f_slider, r));
    EXPECT_EQ(r.norm(), 0.0);
    ASSERT_TRUE(actuator_forces<double>(model, data, by_crank, q, vy, ydd, f_crank, r));
    EXPECT_NEAR(f_slider[0] * v[sc.slider], f_crank[0] * v[sc.crank], 1e-10 * std::max(1.0, std::abs(f_crank[0] * v[sc.crank])));
  }
}

TEST(ActuatorForces, TheSlidersDeadPointIsReported) {
  SliderCrank sc;
  const Model& model = sc.d.model;
  Data<double> data(model);
  const Actuation by_slider = make_actuation(model, {sc.slider});
  // d slider / d crank changes sign where crank and rod align: walk the crank round from the
  // assembled pose (Newton warm-started from the last step) to the first sign change, then bisect.
  const int crank_q = model.q_index_of_v(sc.crank);
  VecX<double> q = sc.d.assembly.q;
  auto slider_rate = [&](double angle, VecX<double>& at) {
    at[crank_q] = angle;
    EXPECT_EQ(closure_positions<double>(model, data, at).status, ClosureStatus::Converged) << angle;
    VecX<double> v(model.nv());
    full_velocities<double>(model, data, at, VecX<double>::Ones(1), v);
    return v[sc.slider];
  };
  double a = q[crank_q];
  const double sa = slider_rate(a, q);
  double b = a;
  for (int k = 0; k < 700; ++k) {
    b += 0.01;
    if (slider_rate(b, q) * sa <= 0) break;
  }
  ASSERT_LE(slider_rate(b, q) * sa, 0.0) << "no dead point of the slider over a crank turn";
  for (int k = 0; k < 200; ++k) {
    const double m = 0.5 * (a + b);
    if (m == a || m == b) break;
    (slider_rate(m, q) * sa > 0 ? a : b) = m;
  }
  const double rate = slider_rate(a, q);
  VecX<double> f(1), r(1);
  const VecX<double> ydd = VecX<double>::Ones(1);
  const bool regular = actuator_forces<double>(model, data, by_slider, q, VecX<double>::Zero(1), ydd, f, r);
  std::printf("  dead point: d slider / d crank = %.1e, force %.1e N, reported %s\n", rate, f[0], regular ? "regular" : "singular");
  EXPECT_TRUE(!regular || std::abs(f[0]) > 1e8) << "a force through a near-zero lever must be reported or huge";
  // Away from it the force is moderate: one hundredth of a radian off.
  VecX<double> off = q;
  slider_rate(a - 0.01, off);
  ASSERT_TRUE(actuator_forces<double>(model, data, by_slider, off, VecX<double>::Zero(1), ydd, f, r));
  EXPECT_LT(std::abs(f[0]), 1e4);
}

TEST(ActuatorForces, RefusalsNameWhatIsWrong) {
  SliderCrank sc;
  const Model& model = sc.d.model;
  auto message = [&](const Model& m, const std::vector<int>& v) {
    try {
      make_actuation(m, v);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(model, {model.nv()}).find("is not one of"), std::string::npos);
  EXPECT_NE(message(model, {sc.crank, sc.crank}).find("listed twice"), std::string::npos);
  // Crank and slider both: one DoF, two actuators, one of them dependent.
  const std::string both = message(model, {sc.crank, sc.slider});
  EXPECT_NE(both.find("rod_slider"), std::string::npos) << both;
  EXPECT_NE(both.find("1 independent coordinate(s) and 2 actuator(s)"), std::string::npos) << both;
  // A floating base.
  const gen::Description lola = load_lola();
  EXPECT_NE(message(lola.model, {3}).find("floating base"), std::string::npos);
  // Through the description: a floating joint named actuated.
  gen::Description named = lola;
  named.actuated_joints = {"root_joint"};
  EXPECT_THROW(gen::actuated_coordinates(named), gen::LoadError);
  named.actuated_joints = {"no_such_joint"};
  try {
    gen::actuated_coordinates(named);
    ADD_FAILURE() << "an unknown joint was accepted";
  } catch (const gen::LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_joint"), std::string::npos) << e.what();
  }
}

// disney_robot's left leg: five actuators, two of them dependent, for five independent
// coordinates of which two are idle spins no actuator moves: the block is singular, so the two
// dependent actuators are left out with a note each (the other three stay, directly).
TEST(ActuatorForces, UnsolvableDependentActuatorsAreLeftOutWithANote) {
  gen::LoadOptions options;
  options.extras_file = MBGEN_TEST_DATA "/parallel_legs/disney_robot_9_of_10.yaml";
  const gen::Description d = gen::load_description(shared_robot("parallel_legs/disney_robot/robot.urdf"), options);
  std::vector<std::string> notes;
  const Actuation act = gen::description_actuation(d, &notes);
  EXPECT_EQ(act.num_actuators(), static_cast<int>(d.actuated_joints.size()) - 2);
  EXPECT_TRUE(act.blocks.empty());
  ASSERT_EQ(notes.size(), 2u);
  for (const char* name : {"left_motor_4barlink1", "left_motor_4barlink4"})
    EXPECT_TRUE(notes[0].find(name) != std::string::npos || notes[1].find(name) != std::string::npos) << name;
  EXPECT_NE(notes[0].find("left out of the actuated set"), std::string::npos) << notes[0];
}

TEST(ActuatorForces, WithoutNamedActuatorsEveryIndependentCoordinateButTheBase) {
  gen::Description d = load_lola();
  d.actuated_joints.clear();
  const std::vector<int> v = gen::actuated_coordinates(d);
  Data<double> data(d.model);
  ASSERT_EQ(v.size(), d.model.structure().independent_v.size() - 6);
  for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(v[i], d.model.structure().independent_v[i + 6]);
}

}  // namespace
}  // namespace mbgen::test
