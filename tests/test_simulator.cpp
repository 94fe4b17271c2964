// The simulator (runtime/include/mbgen/sim/): each integrator's order of convergence, energy
// behaviour, compliant contact against closed forms (a resting box carries m g, a sliding block
// decelerates at mu g), every failure status provoked, and no allocation in a step.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "malloc_guard.hpp"
#include "mbgen/sim/pd_gravity.hpp"
#include "mbgen/sim/simulator.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

using sim::GenericBackend;
using sim::Integrator;
using sim::Simulator;
using sim::SimulatorOptions;
using sim::StepStatus;

constexpr double kG = 9.81;

Inertia<double> point_mass(double m, const Vec3<double>& com, double radius_of_gyration = 0.05) {
  Inertia<double> I;
  I.mass = m;
  I.com = com;
  I.inertia_com = Mat3<double>::Identity() * m * radius_of_gyration * radius_of_gyration;
  return I;
}

/// n links of 0.5 m hanging from revolute joints about y, 1 kg each at the link's end.
Model pendulum_chain(int n) {
  Model model;
  model.name = "pendulum_chain";
  BodyIndex parent = kWorldBody;
  for (int i = 0; i < n; ++i) {
    Joint j;
    j.name = "joint" + std::to_string(i);
    j.axis = Vec3<double>::UnitY();
    if (i > 0) j.X_PJ.translation = Vec3<double>(0, 0, -0.5);
    parent = model.add_body(parent, j, "link" + std::to_string(i), point_mass(1.0, Vec3<double>(0, 0, -0.5)));
  }
  return model;
}

/// A free body (floating base) of mass m.
Model free_body(double m) {
  Model model;
  model.name = "free_body";
  Joint j;
  j.name = "base";
  j.type = JointType::Floating;
  model.add_body(kWorldBody, j, "body", point_mass(m, Vec3<double>::Zero(), 0.1));
  return model;
}

/// The four bottom corners of a 0.2 x 0.1 box below its centre, spheres of radius r.
std::vector<ContactSphere> box_corners(double r) {
  std::vector<ContactSphere> c;
  for (double x : {-0.1, 0.1})
    for (double y : {-0.05, 0.05}) c.push_back({BodyIndex(1), Vec3<double>(x, y, -0.05), r, "corner"});
  return c;
}

VecX<double> base_state(double z) {
  VecX<double> q = VecX<double>::Zero(7);
  q[2] = z;
  q[6] = 1;
  return q;
}

double final_angle_error(Integrator integrator, double h, const VecX<double>& reference) {
  const Model model = pendulum_chain(2);
  SimulatorOptions o;
  o.integrator = integrator;
  o.step = h;
  o.max_step = h;
  o.rtol = o.atol = 1e6;  // dormand_prince45 at a fixed step: its order, not its controller
  Simulator<GenericBackend<double>> sim(GenericBackend<double>(model), o);
  const Eigen::Vector2d q0(0.8, -0.3), v0(0, 0);
  sim.set_state(q0.data(), v0.data());
  EXPECT_EQ(sim.run_until(1.0), StepStatus::ok);
  return (sim.q() - reference).cwiseAbs().maxCoeff();
}

// Each integrator's order, measured on a double pendulum swinging for 1 s from 0.8 / -0.3 rad:
// log2 of the error ratio when the step is halved, within 0.3 of the theory. The reference is
// RK4 at 1e-4 s (its error ~1e-14 there).
TEST(SimulatorOrder, EveryIntegratorConvergesAtItsOrder) {
  const Model model = pendulum_chain(2);
  SimulatorOptions o;
  o.step = 1e-4;
  Simulator<GenericBackend<double>> reference(GenericBackend<double>(model), o);
  const Eigen::Vector2d q0(0.8, -0.3), v0(0, 0);
  reference.set_state(q0.data(), v0.data());
  ASSERT_EQ(reference.run_until(1.0), StepStatus::ok);
  struct Case {
    Integrator integrator;
    double h;
  };
  for (const Case& c : {Case{Integrator::explicit_euler, 1e-3}, Case{Integrator::symplectic_euler, 1e-3},
                        Case{Integrator::rk4, 2e-2}, Case{Integrator::dormand_prince45, 1e-2},
                        Case{Integrator::linearly_implicit_euler, 1e-3}}) {
    const double coarse = final_angle_error(c.integrator, c.h, reference.q());
    const double fine = final_angle_error(c.integrator, c.h / 2, reference.q());
    const double slope = std::log2(coarse / fine);
    EXPECT_NEAR(slope, sim::order_of(c.integrator), 0.3)
        << sim::to_string(c.integrator) << ": errors " << coarse << " at h, " << fine << " at h/2";
    std::printf("[ order    ] %-24s h %.0e: error %.2e, h/2: %.2e, slope %.2f\n", sim::to_string(c.integrator), c.h, coarse,
                fine, slope);
  }
}

/// max |E - E0| over [from, to) s, sampled every 0.01 s, for a 1-DoF pendulum released at 1 rad.
std::pair<double, double> energy_errors(Integrator integrator) {
  const Model model = pendulum_chain(1);
  SimulatorOptions o;
  o.integrator = integrator;
  o.step = 1e-3;
  o.energy_check_interval = 0;
  Simulator<GenericBackend<double>> sim(GenericBackend<double>(model), o);
  const double q0 = 1.0, v0 = 0;
  sim.set_state(&q0, &v0);
  const double e0 = sim.energy();
  double first = 0, second = 0;
  for (int k = 1; k <= 1000; ++k) {
    EXPECT_EQ(sim.run_until(0.01 * k), StepStatus::ok);
    (k <= 500 ? first : second) = std::max(k <= 500 ? first : second, std::abs(sim.energy() - e0));
  }
  return {first, second};
}

// Over 10 s at 1 ms: symplectic Euler's energy error oscillates and stays bounded (the second
// five seconds no worse than the first), explicit Euler's keeps growing.
TEST(SimulatorEnergy, SymplecticEulerStaysBoundedExplicitEulerGrows) {
  const auto [se_first, se_second] = energy_errors(Integrator::symplectic_euler);
  const auto [ee_first, ee_second] = energy_errors(Integrator::explicit_euler);
  std::printf("[ energy   ] symplectic Euler: max |dE| %.3g J (0-5 s), %.3g J (5-10 s); explicit Euler: %.3g, %.3g\n",
              se_first, se_second, ee_first, ee_second);
  EXPECT_LT(se_second, 1.1 * se_first);
  EXPECT_LT(se_second, 0.05);  // J, of |E| ~ 2.3 J: O(h) and bounded
  EXPECT_GT(ee_second, 1.5 * ee_first);
  EXPECT_GT(ee_second, 10 * se_second);
}

// A box on four corner spheres, released touching the ground, settles and carries its weight:
// the normal forces add up to m g (1e-6 relative) and share it equally (symmetry).
TEST(SimulatorContact, RestingBoxCarriesItsWeight) {
  const double m = 2.0;
  const Model model = free_body(m);
  SimulatorOptions o;
  o.step = 1e-4;
  Simulator<GenericBackend<double>> sim(GenericBackend<double>(model, box_corners(0.01)), o);
  const VecX<double> q = base_state(0.06), v = VecX<double>::Zero(6);
  sim.set_state(q.data(), v.data());
  ASSERT_EQ(sim.run_until(3.0), StepStatus::ok);
  double total = 0;
  for (const auto& c : sim.contacts()) {
    EXPECT_TRUE(c.active);
    EXPECT_NEAR(c.normal_force, m * kG / 4, 1e-6 * m * kG);
    total += c.normal_force;
  }
  EXPECT_NEAR(total, m * kG, 1e-6 * m * kG);
  std::printf("[ resting  ] sum of normal forces %.9f N for m g = %.9f N, penetration %.3g m\n", total, m * kG,
              sim.contacts()[0].penetration);
}

// A point-contact block sliding at 1 m/s on mu = 0.5 decelerates at exactly mu g (slip far
// above the stiction velocity; it starts at its static penetration, so the normal force is m g).
TEST(SimulatorContact, SlidingBlockDeceleratesAtMuG) {
  const double m = 2.0;
  const Model model = free_body(m);
  SimulatorOptions o;
  o.step = 1e-4;
  o.contact_parameters.friction = 0.5;
  const double static_penetration = std::pow(m * kG / o.contact_parameters.stiffness, 1 / o.contact_parameters.exponent);
  Simulator<GenericBackend<double>> sim(GenericBackend<double>(model, {{BodyIndex(1), Vec3<double>::Zero(), 0.0, "point"}}), o);
  VecX<double> q = base_state(-static_penetration), v = VecX<double>::Zero(6);
  v[0] = 1.0;
  sim.set_state(q.data(), v.data());
  ASSERT_EQ(sim.run_until(0.1), StepStatus::ok);
  EXPECT_NEAR(sim.v()[0], 1.0 - 0.5 * kG * 0.1, 1e-10);
  EXPECT_NEAR(sim.contacts()[0].force.x(), -0.5 * m * kG, 1e-8 * m * kG);
  EXPECT_NEAR(sim.contacts()[0].normal_force, m * kG, 1e-8 * m * kG);
}

// --- every failure status, provoked --------------------------------------------------------

// Explicit Euler at 2 ms on a contact of natural period ~8 ms: unstable; the energy bound
// catches it, and the state is the last good one (finite).
TEST(SimulatorFailure, ExplicitEulerTooCoarseForTheContactDiverges) {
  const Model model = free_body(2.0);
  SimulatorOptions o;
  o.integrator = Integrator::explicit_euler;
  o.step = 2e-3;
  o.max_penetration = 1.0;
  o.energy_check_interval = 1;
  Simulator<GenericBackend<double>> sim(GenericBackend<double>(model, box_corners(0.01)), o);
  const VecX<double> q = base_state(0.1), v = VecX<double>::Zero(6);
  sim.set_state(q.data(), v.data());
  EXPECT_EQ(sim.run_until(2.0), StepStatus::diverged);
  EXPECT_LT(sim.time(), 2.0);
  EXPECT_TRUE(sim.q().allFinite() && sim.v().allFinite());
  // The same drop with the contact-implicit integrator at the same step is fine.
  o.integrator = Integrator::linearly_implicit_euler;
  Simulator<GenericBackend<double>> stiff(GenericBackend<double>(model, box_corners(0.01)), o);
  stiff.set_state(q.data(), v.data());
  EXPECT_EQ(stiff.run_until(2.0), StepStatus::ok);
  EXPECT_NEAR(stiff.q()[2], 0.06, 1e-3);
}

// A soft ground lets a box dropped from 0.5 m sink beyond max_penetration.
TEST(SimulatorFailure, SoftGroundReportsPenetration) {
  const Model model = free_body(2.0);
  SimulatorOptions o;
  o.contact_parameters.stiffness = 1e3;
  o.max_penetration = 0.02;
  Simulator<GenericBackend<double>> sim(GenericBackend<double>(model, box_corners(0.01)), o);
  const VecX<double> q = base_state(0.5), v = VecX<double>::Zero(6);
  sim.set_state(q.data(), v.data());
  EXPECT_EQ(sim.run_until(1.0), StepStatus::penetration);
  EXPECT_GT(sim.time(), 0.2);  // it fell ~0.44 m first
}

// A NaN joint force from the controller: diverged at once, the state untouched.
TEST(SimulatorFailure, NanJointForceIsReported) {
  const Model model = pendulum_chain(2);
  Simulator<GenericBackend<double>> sim{GenericBackend<double>(model)};
  const Eigen::Vector2d q0(0.1, 0.2), v0(0, 0);
  sim.set_state(q0.data(), v0.data());
  ASSERT_EQ(sim.run_until(0.01), StepStatus::ok);
  const VecX<double> before = sim.q();
  sim.set_controller([](double t, const double*, const double*, double* tau) {
    tau[0] = t > 0.02 ? std::numeric_limits<double>::quiet_NaN() : 0.0;
    tau[1] = 0;
  });
  EXPECT_EQ(sim.run_until(0.1), StepStatus::diverged);
  EXPECT_NEAR(sim.time(), 0.021, 1e-9);
  EXPECT_TRUE(sim.q().allFinite() && sim.v().allFinite());
}

gen::Description load_mechanism(const std::string& urdf, const std::string& yaml) {
  gen::LoadOptions options;
  options.extras_file = yaml;
  gen::Description d = gen::load_description(urdf, options);
  EXPECT_EQ(d.assembly.q.size(), d.model.nq()) << urdf << ": no loops were loaded";
  return d;
}

// The four-bar with the full-coordinate reference, no projection, and Baumgarte gains far too
// high for the step (alpha = beta = 1e4 /s against RK4 at 1 ms): the constraint's own dynamics
// are unstable, the energy bound catches it. Moderate gains (10 /s) run.
TEST(SimulatorFailure, BaumgarteGainsTooHighDiverge) {
  const gen::Description d = load_mechanism(MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.urdf", MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.yaml");
  SimulatorOptions o;
  o.step = 1e-3;
  o.project = false;
  o.energy_check_interval = 1;
  for (double gain : {1e4, 10.0}) {
    Simulator<sim::KktBackend<double>> sim(sim::KktBackend<double>(d.model, {gain, gain}), o);
    const VecX<double> v = VecX<double>::Zero(d.model.nv());
    sim.set_state(d.assembly.q.data(), v.data());
    EXPECT_EQ(sim.run_until(1.0), gain > 100 ? StepStatus::diverged : StepStatus::ok) << "gains " << gain;
  }
}

// The generic backend in float (its closure options float's: 2e-6, default_closure_options):
// the four-bar swinging from 3 rad/s for 0.5 s with RK4 at 1e-3 s stays with the double run to
// float's precision (measured 9.6e-6 rad), the loop closed to the float tolerance.
TEST(SimulatorFloat, GenericBackendSwingsTheFourBarInFloat) {
  const gen::Description d = load_mechanism(MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.urdf", MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.yaml");
  SimulatorOptions o;
  o.step = 1e-3;
  Simulator<GenericBackend<double>> in_double{GenericBackend<double>(d.model), o};
  Simulator<GenericBackend<float>> in_float{GenericBackend<float>(d.model), o};
  VecX<double> v(d.model.nv()), vy = VecX<double>::Constant(in_double.backend().ny(), 3.0);
  in_double.backend().full_velocities(d.assembly.q.data(), vy.data(), v.data());
  const VecX<float> qf = d.assembly.q.cast<float>(), vf = v.cast<float>();
  ASSERT_EQ(in_double.set_state(d.assembly.q.data(), v.data()), 0);
  ASSERT_EQ(in_float.set_state(qf.data(), vf.data()), 0);
  ASSERT_EQ(in_double.run_until(0.5), StepStatus::ok);
  ASSERT_EQ(in_float.run_until(0.5), StepStatus::ok);
  const double deviation = (in_float.q().cast<double>() - in_double.q()).cwiseAbs().maxCoeff();
  std::printf("four-bar in float against double after 0.5 s: %.2g rad\n", deviation);
  EXPECT_LT(deviation, 1e-4);
  EXPECT_GT(deviation, 1e-9);  // it did run in float
  Data<double> data(d.model);
  closure_residual<double>(d.model, data, in_float.q().cast<double>());
  EXPECT_LT(data.Phi.cwiseAbs().maxCoeff(), 1e-5);
}

/// The slider-driven slider-crank at its assembled pose, at rest, its slider pushed by 50 N
/// towards the stroke end (its dead point at 0.06 m); returns the slider's v index.
int push_the_slider(Simulator<GenericBackend<double>>& sim, const gen::Description& d) {
  const VecX<double> v = VecX<double>::Zero(d.model.nv());
  sim.set_state(d.assembly.q.data(), v.data());
  const int slider = sim.backend().independent_v_index()[0];
  sim.set_controller([slider, nv = d.model.nv()](double, const double*, const double*, double* tau) {
    for (int i = 0; i < nv; ++i) tau[i] = 0;
    tau[slider] = 50;  // N, towards the stroke end
  });
  return slider;
}

// The slider-crank driven by its slider, pushed to the stroke end (its dead point, slider at
// 0.06 m): the closure reports it, the simulation stops before it. The step (1 ms) carries the
// slider past the stroke end, where no closed pose exists: Newton stops at the dead point
// (singular) or runs out of iterations (not converged), which of the two depends on the last
// bits of the iterates. With 0.1 ms steps RK4 may instead resolve the turn, and the slider comes
// back as the real mechanism's would with its crank turning on; whether it does depends on the
// rounding as well (it did once the Givens rotations took one division instead of three).
TEST(SimulatorFailure, SliderCrankThroughItsDeadPointLosesTheClosure) {
  const gen::Description d = load_mechanism(MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.urdf",
                                            MBGEN_TEST_DATA "/mechanisms/slider_crank_slider_driven.yaml");
  SimulatorOptions o;
  o.step = 1e-3;
  Simulator<GenericBackend<double>> sim{GenericBackend<double>(d.model), o};
  const int slider = push_the_slider(sim, d);
  EXPECT_EQ(sim.run_until(2.0), StepStatus::closure_lost);
  EXPECT_TRUE(sim.closure_status() == static_cast<int>(ClosureStatus::Singular) ||
              sim.closure_status() == static_cast<int>(ClosureStatus::NotConverged))
      << sim.closure_status();
  ASSERT_EQ(sim.closure_subsystem(), 0);
  EXPECT_STREQ(sim.backend().subsystem_name(0), "rod_slider");
  EXPECT_TRUE(sim.q().allFinite() && sim.v().allFinite());
  EXPECT_LT(sim.q()[slider], 0.06);
  EXPECT_GT(sim.q()[slider], 0.05);
}

// The same push with the continuation on (SimulatorOptions::continuation): the step that cannot
// close the loop is taken again with the loop soft, the run goes on through the dead point, the
// crank turns on and the slider comes back (the 50 N is a conservative force: it returns to its
// start with the crank a turn further, and goes out again). Every span is reported: it names
// rod_slider, it closes again, and its largest violation is the largest |Phi| of the kept rows
// at its accepted states, which the test measures itself with the runtime's closure_residual.
// Outside the spans the loop is closed as ever (1e-11, the projection's tolerance).
TEST(SimulatorContinuation, SliderCrankRunsThroughItsDeadPoint) {
  const gen::Description d = load_mechanism(MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.urdf",
                                            MBGEN_TEST_DATA "/mechanisms/slider_crank_slider_driven.yaml");
  SimulatorOptions o;
  o.step = 1e-3;
  o.continuation.enabled = true;
  Simulator<GenericBackend<double>> sim{GenericBackend<double>(d.model), o};
  const int slider = push_the_slider(sim, d);
  Data<double> data(d.model);
  const SubSystem& sub = d.model.subsystems.at(0);
  const auto kept_violation = [&] {
    const VecX<double>& Phi = closure_residual<double>(d.model, data, sim.q());
    double worst = 0;
    for (int row : sub.rows) worst = std::max(worst, std::abs(Phi[row]));
    return worst;
  };
  double soft_violation = 0, exact_violation = 0, slider_max = -1, slider_min_after = 1;
  long soft_steps = 0;
  bool passed = false;
  std::size_t soft_allocations = 0;
  while (sim.time() < 2.0 - 1e-9) {
    const bool first = sim.time() == 0;  // the first step warms up (as in SimulatorAllocation)
    MallocGuard guard;
    const StepStatus s = sim.step();
    // No step allocates: the ones that enter a span, the soft ones, the one that leaves.
    if (!first) soft_allocations += guard.count();
    ASSERT_TRUE(sim::advanced(s)) << sim::to_string(s) << " at " << sim.time();
    const double x = sim.q()[slider];
    slider_max = std::max(slider_max, x);
    if (s == StepStatus::continued) {
      ++soft_steps;
      passed = true;
      if (sim.in_continuation()) soft_violation = std::max(soft_violation, kept_violation());
    } else {
      exact_violation = std::max(exact_violation, kept_violation());
    }
    if (passed) slider_min_after = std::min(slider_min_after, x);
  }
  EXPECT_EQ(soft_allocations, 0u) << "a step allocated";
  const auto& spans = sim.continuation_spans();
  ASSERT_FALSE(spans.empty());
  EXPECT_EQ(sim.statistics().continuation_spans, static_cast<long>(spans.size()));
  EXPECT_EQ(sim.statistics().soft_steps, soft_steps);
  double reported = 0;
  for (const sim::ContinuationSpan& span : spans) {
    EXPECT_EQ(span.subsystem, 0);
    EXPECT_FALSE(span.diverged);
    EXPECT_STREQ(sim.backend().subsystem_name(span.subsystem), "rod_slider");
    EXPECT_GT(span.steps, 0);
    if (&span != &spans.back() || !sim.in_continuation()) {
      EXPECT_GT(span.end, span.begin);  // closed again
    }
    reported = std::max(reported, span.max_violation);
    std::printf("[ continue ] span %.4f .. %.4f s, %ld soft steps, largest violation %.3g m\n", span.begin, span.end, span.steps,
                span.max_violation);
  }
  // The last soft step of a span closes the loop (its violation is measured before): the test's
  // own maximum over the steps still soft is at most the reported one, which the exit step adds.
  EXPECT_LE(soft_violation, reported);
  EXPECT_EQ(sim.statistics().max_loop_violation, reported);
  EXPECT_GT(reported, 0);
  EXPECT_LT(reported, 1e-5);  // m: soft, not loose (1.5e-6 m)
  // The 50 N is conservative: no energy is gained, and the spans' softness loses little of the
  // 3 J each stroke turns over (5e-3 J in 2 s, 21 spans).
  EXPECT_LT(sim.energy_balance(), 1e-3);
  EXPECT_GT(sim.energy_balance(), -0.02);
  EXPECT_LT(exact_violation, 1e-10);
  EXPECT_LE(slider_max, 0.06 + reported + 1e-6);  // the stroke end, within the loop's give
  EXPECT_GT(slider_max, 0.0599);
  EXPECT_LT(slider_min_after, 0.03) << "the slider comes back";
  std::printf("[ continue ] slider-crank 2 s: %zu spans, %ld soft steps of %ld, slider back to %.4f m, energy balance %.3g J\n",
              spans.size(), soft_steps, sim.statistics().accepted_steps, slider_min_after, sim.energy_balance());
}

// Each option of the continuation does what docs/simulation.md says, on the same push for 0.3 s
// (three dead points): softer rows (t_c 10 ms, d 0.99) open the loop wider and lose more energy;
// entering only where Newton fails (enter_pivot_ratio 0) lets the last exact step before the first
// dead point take out over a joule (0.06 s, past it); max_spans bounds the list, not the count.
TEST(SimulatorContinuation, OptionsChangeWhatTheySay) {
  const gen::Description d = load_mechanism(MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.urdf",
                                            MBGEN_TEST_DATA "/mechanisms/slider_crank_slider_driven.yaml");
  struct Run {
    double violation, energy;
    long spans, soft_steps;
    std::size_t listed;
  };
  const auto run = [&](const sim::ContinuationOptions& c, double duration = 0.3) {
    SimulatorOptions o;
    o.step = 1e-3;
    o.continuation = c;
    o.continuation.enabled = true;
    Simulator<GenericBackend<double>> sim{GenericBackend<double>(d.model), o};
    push_the_slider(sim, d);
    EXPECT_EQ(sim.run_until(duration), StepStatus::continued);
    return Run{sim.statistics().max_loop_violation, sim.energy_balance(), sim.statistics().continuation_spans,
               sim.statistics().soft_steps, sim.continuation_spans().size()};
  };
  const sim::ContinuationOptions defaults;
  sim::ContinuationOptions softer, late, short_list, late_exit;
  softer.time_constant = 0.01, softer.impedance = 0.99;
  late.enter_pivot_ratio = 0;
  short_list.max_spans = 1;
  late_exit.exit_pivot_ratio = 0.6;  // the loops must be further from the dead point to close again
  const Run a = run(defaults), b = run(softer), c = run(late, 0.06), e = run(short_list), a_first = run(defaults, 0.06);
  std::printf("[ continue ] 0.3 s: default %ld spans, violation %.2g m, energy %.3g J; softer %.2g m, %.3g J; entering late %.3g J\n",
              a.spans, a.violation, a.energy, b.violation, b.energy, c.energy);
  EXPECT_GE(a.spans, 3);
  EXPECT_GT(b.violation, 5 * a.violation);
  EXPECT_LT(b.energy, 2 * a.energy);
  EXPECT_LT(c.energy, -1.0);
  EXPECT_GT(a_first.energy, -0.05);
  EXPECT_GT(a.energy, -0.05);
  EXPECT_EQ(a.listed, static_cast<std::size_t>(a.spans));
  EXPECT_EQ(e.spans, a.spans);
  EXPECT_EQ(e.listed, 1u);
  const Run f = run(late_exit);
  EXPECT_GT(f.soft_steps, a.soft_steps + a.spans) << "longer spans";
}

// A backend without closure_constraints (one generated before it existed) cannot continue: the
// simulator says so at set_state instead of failing at the first dead point.
struct BackendWithoutClosureConstraints : GenericBackend<double> {
  using GenericBackend<double>::GenericBackend;
  void closure_constraints(const double*, const double*, double*, double*, double*) = delete;
};

TEST(SimulatorContinuation, ABackendWithoutClosureConstraintsIsRefused) {
  const gen::Description d = load_mechanism(MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.urdf",
                                            MBGEN_TEST_DATA "/mechanisms/slider_crank_slider_driven.yaml");
  SimulatorOptions o;
  o.continuation.enabled = true;
  Simulator<BackendWithoutClosureConstraints> sim{BackendWithoutClosureConstraints(d.model), o};
  const VecX<double> v = VecX<double>::Zero(d.model.nv());
  try {
    sim.set_state(d.assembly.q.data(), v.data());
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("closure_constraints"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("regenerate"), std::string::npos) << e.what();
  }
}

// The exact behaviour stays the default, and the option changes nothing where no span is needed.
TEST(SimulatorContinuation, OffByDefault) {
  EXPECT_FALSE(SimulatorOptions{}.continuation.enabled);
  const gen::Description d = load_mechanism(MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.urdf",
                                            MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.yaml");
  SimulatorOptions o;
  o.continuation.enabled = true;
  o.continuation.max_spans = 3;
  Simulator<GenericBackend<double>> sim{GenericBackend<double>(d.model), o};
  const VecX<double> v = VecX<double>::Zero(d.model.nv());
  ASSERT_EQ(sim.set_state(d.assembly.q.data(), v.data()), 0);
  // A regular mechanism swinging under gravity never needs a span: the same bits as without.
  Simulator<GenericBackend<double>> exact{GenericBackend<double>(d.model), SimulatorOptions{}};
  exact.set_state(d.assembly.q.data(), v.data());
  EXPECT_EQ(sim.run_until(0.2), StepStatus::ok);
  EXPECT_EQ(exact.run_until(0.2), StepStatus::ok);
  EXPECT_EQ(sim.q(), exact.q());
  EXPECT_TRUE(sim.continuation_spans().empty());
  EXPECT_EQ(sim.statistics().soft_steps, 0);
}

// Dormand-Prince rejects steps where the contact switches on, and stops with step_rejected when
// its step would have to fall below min_step.
TEST(SimulatorFailure, AdaptiveStepsAreRejectedAndCanRunOut) {
  const Model model = free_body(2.0);
  SimulatorOptions o;
  o.integrator = Integrator::dormand_prince45;
  o.step = 1e-3;
  o.rtol = 1e-8;
  o.atol = 1e-10;
  Simulator<GenericBackend<double>> sim(GenericBackend<double>(model, box_corners(0.01)), o);
  const VecX<double> q = base_state(0.1), v = VecX<double>::Zero(6);
  sim.set_state(q.data(), v.data());
  EXPECT_EQ(sim.run_until(0.5), StepStatus::ok);
  EXPECT_GT(sim.statistics().rejected_steps, 0);
  std::printf("[ dopri    ] box drop 0.5 s: %ld accepted, %ld rejected steps\n", sim.statistics().accepted_steps,
              sim.statistics().rejected_steps);
  o.min_step = 1e-3;
  Simulator<GenericBackend<double>> coarse(GenericBackend<double>(model, box_corners(0.01)), o);
  coarse.set_state(q.data(), v.data());
  EXPECT_EQ(coarse.run_until(0.5), StepStatus::step_rejected);
}

// A stiff torsional spring (1000 N m/rad) on a pendulum: as a passive force (every stage) the
// energy balance, with the spring's work counted, stays at round-off level; the same law through
// the controller held over each step (zero-order hold) is explicit Euler on the spring and drifts.
TEST(SimulatorPassive, SpringsAreEvaluatedAtEveryStage) {
  // A stiff joint spring on a pendulum (k = 1000 N m/rad): its potential 1/2 k q^2 plus the
  // mechanical energy is conserved by the physics. As a passive force it is evaluated at every
  // RK4 stage and the total stays put; written by a controller and held over each step, it is
  // explicit Euler on the spring and the total drifts by orders of magnitude more. Both energy
  // balances (which count the spring's work as an external force's) are exact to the
  // integrator's order: the work is integrated with the RK4 weights.
  const Model model = pendulum_chain(1);
  SimulatorOptions o;
  o.step = 1e-3;
  o.energy_check_interval = 0;
  const double k = 1000;
  const auto spring = [k](const double* q, const double*, double* tau) { tau[0] -= k * q[0]; };
  Simulator<GenericBackend<double>> passive(GenericBackend<double>(model), o);
  passive.set_passive_forces(spring);
  const double q0 = 0.2, v0 = 0;
  passive.set_state(&q0, &v0);
  const double total_start = passive.energy() + 0.5 * k * q0 * q0;
  ASSERT_EQ(passive.run_until(1.0), StepStatus::ok);
  o.control_period = 0;  // the controller at every step, held over it
  Simulator<GenericBackend<double>> held(GenericBackend<double>(model), o);
  held.set_controller([spring](double, const double* q, const double* v, double* tau) {
    tau[0] = 0;
    spring(q, v, tau);
  });
  held.set_state(&q0, &v0);
  ASSERT_EQ(held.run_until(1.0), StepStatus::ok);
  const auto total_drift = [&](Simulator<GenericBackend<double>>& s) {
    const double q = s.q()[0];
    return std::abs(s.energy() + 0.5 * k * q * q - total_start);
  };
  std::printf("[ passive  ] after 1 s: spring + mechanical energy drift %.2e J passive, %.2e J held; "
              "balance %.2e J, %.2e J\n",
              total_drift(passive), total_drift(held), passive.energy_balance(), held.energy_balance());
  // The spring holds 20 J; RK4's own error at this step is ~1e-6 of it (measured 1.8e-5 J, and
  // 124 J gained by the held spring).
  EXPECT_LT(total_drift(passive), 1e-4);
  EXPECT_GT(total_drift(held), 1e5 * total_drift(passive));
  EXPECT_LT(std::abs(passive.energy_balance()), 1e-4);
  EXPECT_LT(std::abs(held.energy_balance()), 1e-4);
}

// --- the controller ---------------------------------------------------------------------------

// PD + gravity holds the four-bar's assembled pose: at the target with v = 0, the accelerations
// vanish (gravity compensated through the loop, T^T g).
TEST(PdGravity, HoldsAClosedLoopAtItsTarget) {
  const gen::Description d = load_mechanism(MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.urdf", MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.yaml");
  GenericBackend<double> backend(d.model);
  const int ny = backend.ny();
  sim::PdGravityController<GenericBackend<double>> pd(GenericBackend<double>(d.model), d.assembly.q, VecX<double>::Constant(ny, 10),
                                                       VecX<double>::Constant(ny, 1));
  VecX<double> tau(d.model.nv()), qdd(d.model.nv());
  const VecX<double> v = VecX<double>::Zero(d.model.nv());
  pd(0, d.assembly.q.data(), v.data(), tau.data());
  backend.accelerations(d.assembly.q.data(), v.data(), tau.data(), qdd.data());
  EXPECT_LT(qdd.cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_GT(tau.cwiseAbs().maxCoeff(), 1e-3);  // it did have to hold something
}

// --- no allocation --------------------------------------------------------------------------

TEST(SimulatorAllocation, AStepAllocatesNothing) {
  const gen::Description d = load_mechanism(MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.urdf", MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.yaml");
  const Model box = free_body(2.0);
  for (Integrator integrator : {Integrator::explicit_euler, Integrator::symplectic_euler, Integrator::rk4,
                                Integrator::dormand_prince45, Integrator::linearly_implicit_euler}) {
    SimulatorOptions o;
    o.integrator = integrator;
    o.step = 1e-4;
    Simulator<GenericBackend<double>> loops{GenericBackend<double>(d.model), o};
    const VecX<double> v = VecX<double>::Zero(d.model.nv());
    loops.set_state(d.assembly.q.data(), v.data());
    Simulator<GenericBackend<double>> contact(GenericBackend<double>(box, box_corners(0.01)), o);
    const VecX<double> q = base_state(0.0595), v6 = VecX<double>::Zero(6);
    contact.set_state(q.data(), v6.data());
    loops.set_controller([](double, const double*, const double*, double* tau) { tau[0] = 0.1; });
    ASSERT_EQ(loops.step(), StepStatus::ok);
    ASSERT_EQ(contact.step(), StepStatus::ok);
    MallocGuard guard;
    for (int k = 0; k < 20; ++k) {
      loops.step();
      contact.step();
    }
    EXPECT_EQ(guard.count(), 0u) << sim::to_string(integrator);
  }
}

}  // namespace
}  // namespace mbgen::test
