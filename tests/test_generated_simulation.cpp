// The generated backend (NAME::Backend, emitted in the header) against the generic one, through
// the same simulator: Lola standing on its feet with the ground pressing 12 contact spheres, and
// the four-bar swinging. One step of each integrator agrees to 1e-12 in double, and the
// generated contact_points equal the generic ones.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "collision/collision_scene.hpp"
#include "collision/contact_spheres.hpp"
#include "model/actuated_coordinates.hpp"
#include "four_bar.hpp"
#include "lola.hpp"
#include "mbgen/sim/pd_gravity.hpp"
#include "mbgen/sim/simulator.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

using sim::Integrator;
using sim::StepStatus;

// The backends' actuator_forces: the generic one, given the description's actuated set
// (set_actuated), equals the generated one (1e-12); set_actuated refuses what make_actuation does.
TEST(GeneratedSimulation, ActuatorForcesOfBothBackendsAgree) {
  const gen::Description d = load_lola();
  sim::GenericBackend<double> generic(d.model);
  generic.set_actuated(gen::actuated_coordinates(d));
  const lola::Backend generated;
  ASSERT_EQ(generic.na(), generated.na());
  for (int i = 0; i < generic.na(); ++i) EXPECT_EQ(generic.actuated_v_index()[i], generated.actuated_v_index()[i]);
  std::mt19937_64 rng(9);
  double worst = 0;
  for (int trial = 0; trial < 10; ++trial) {
    VecX<double> q, v;
    ASSERT_TRUE(consistent_state(d.model, d.assembly.q, rng, 0.05, q, v));
    VecX<double> vy(lola::ny), ydd = random_vector<double>(lola::ny, rng, 5.0);
    lola::independent_velocities(v.data(), vy.data());
    VecX<double> f(lola::na), r(lola::ny), f_gen(lola::na), r_gen(lola::ny);
    generic.actuator_forces(q.data(), vy.data(), ydd.data(), f.data(), r.data());
    generated.actuator_forces(q.data(), vy.data(), ydd.data(), f_gen.data(), r_gen.data());
    worst = std::max({worst, relative_error(f_gen, f), relative_error(r_gen, r)});
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_THROW(generic.set_actuated({0}), std::invalid_argument);  // a floating-base coordinate
}

// The backends' self_distances_near: the generic one, given the generator's collision scene,
// returns the generated one's near list, distances (1e-12) and compact Jacobian rows (1e-12 of
// the largest entry) on Lola's closed poses; without a collision model it reports no pair.
TEST(GeneratedSimulation, NearDistancesOfBothBackendsAgree) {
  const gen::Description d = load_lola();
  const collision::CollisionModel cm = gen::build_collision_scene(d, gen::collision_scene_options(d)).model;
  sim::GenericBackend<double> generic(d.model);
  int none = -1;
  generic.self_distances_near(d.assembly.q.data(), 0.05, nullptr, nullptr, &none, nullptr, nullptr, nullptr);
  EXPECT_EQ(none, 0);
  generic.set_collision_model(&cm);
  const lola::Backend generated;
  const int np = lola::num_distance_pairs, nv = lola::nv;
  ASSERT_EQ(generic.num_distance_pairs(), np);
  std::vector<double> d1(np), n1(3 * np), w1(6 * np), J1(np * nv), d2(np), n2(3 * np), w2(6 * np), J2(np * nv);
  std::vector<int> near1(np), near2(np);
  std::mt19937_64 rng(17);
  double worst = 0;
  int most = 0;
  for (int trial = 0; trial < 10; ++trial) {
    VecX<double> q, v;
    ASSERT_TRUE(consistent_state(d.model, d.assembly.q, rng, 0.3, q, v));
    int m1 = -1, m2 = -1;
    generic.self_distances_near(q.data(), 0.05, d1.data(), near1.data(), &m1, n1.data(), w1.data(), J1.data());
    generated.self_distances_near(q.data(), 0.05, d2.data(), near2.data(), &m2, n2.data(), w2.data(), J2.data());
    ASSERT_EQ(m1, m2) << trial;
    most = std::max(most, m1);
    for (int i = 0; i < m1; ++i) ASSERT_EQ(near1[i], near2[i]) << trial;
    double jscale = 1;
    for (int i = 0; i < m1 * nv; ++i) jscale = std::max(jscale, std::abs(J1[i]));
    for (int k = 0; k < np; ++k) worst = std::max(worst, std::abs(d1[k] - d2[k]));
    for (int i = 0; i < m1 * nv; ++i) worst = std::max(worst, std::abs(J1[i] - J2[i]) / jscale);
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(most, 0);
}

TEST(GeneratedSimulation, ContactPointsEqualTheGenericOnes) {
  const gen::Description d = load_lola();
  const std::vector<ContactSphere> spheres = gen::contact_spheres(d);
  ASSERT_EQ(static_cast<int>(spheres.size()), lola::num_contact_spheres);
  Data<double> data(d.model);
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 5; ++trial) {
    const VecX<double> q = random_configuration<double>(d.model, rng);
    VecX<double> p(3 * spheres.size()), J(6 * d.model.nv() * spheres.size()), pg(p.size()), Jg(J.size());
    contact_points<double>(d.model, data, spheres, q, p.data(), J.data());
    lola::contact_points(q.data(), pg.data(), Jg.data());
    EXPECT_LT((p - pg).cwiseAbs().maxCoeff(), 1e-13);
    EXPECT_LT((J - Jg).cwiseAbs().maxCoeff(), 1e-13);
  }
  for (int k = 0; k < lola::num_contact_spheres; ++k) {
    EXPECT_EQ(spheres[static_cast<std::size_t>(k)].name, lola::contact_sphere_names[k]);
    EXPECT_EQ(spheres[static_cast<std::size_t>(k)].radius, lola::contact_sphere_radius[k]);
  }
}

// The generated contact_accelerations (contact kinematics, law, J^T f and the closed-system
// dynamics in one unrolled function) against the generic contact_joint_forces followed by the
// O(n) recursion: Lola lowered 1 mm into the ground, moving (sliding, sinking, turning, legs
// swinging), so that some spheres press and slip and others are apart. Accelerations to 1e-10
// relative to their largest, the per-sphere outputs to 1e-10 relative.
TEST(GeneratedSimulation, ContactAccelerationsEqualTheGenericOnes) {
  const gen::Description d = load_lola();
  const std::vector<ContactSphere> spheres = gen::contact_spheres(d);
  sim::GenericBackend<double> generic(d.model, spheres);
  generic.set_contact_exponent(lola::contact_exponent);
  const lola::Backend generated;
  EXPECT_EQ(generated.contact_exponent(), lola::contact_exponent);
  ContactParameters p;
  p.stiffness = lola::contact_stiffness, p.damping = lola::contact_damping, p.friction = lola::contact_friction;
  p.stiction_velocity = lola::contact_stiction_velocity;
  double ground[kGroundInputs], law[kLawInputs];
  contact_inputs(GroundPlane::tilted_about_x(0.05), p, ground, law);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  int pressing = 0, apart = 0;
  for (int trial = 0; trial < 4; ++trial) {
    const VecX<double> q = sunk_into_ground(d, spheres, 1e-3);
    VecX<double> vy(generic.ny()), v(d.model.nv()), tau(d.model.nv());
    for (int i = 0; i < vy.size(); ++i) vy[i] = 0.3 * unit(rng);
    for (int i = 0; i < tau.size(); ++i) tau[i] = 20 * unit(rng);
    generic.full_velocities(q.data(), vy.data(), v.data());
    const int nc = lola::num_contact_spheres;
    VecX<double> qdd(d.model.nv()), qdd_g(d.model.nv()), out(kContactOutputs * nc), out_g(out.size());
    generic.accelerations_with_contact(q.data(), v.data(), tau.data(), ground, law, qdd.data(), out.data());
    generated.accelerations_with_contact(q.data(), v.data(), tau.data(), ground, law, qdd_g.data(), out_g.data());
    EXPECT_LT((qdd - qdd_g).cwiseAbs().maxCoeff(), 1e-10 * qdd.cwiseAbs().maxCoeff()) << trial;
    EXPECT_LT((out - out_g).cwiseAbs().maxCoeff(), 1e-10 * out.cwiseAbs().maxCoeff()) << trial;
    for (int k = 0; k < nc; ++k) (out[kContactOutputs * k] > 0 ? pressing : apart) += 1;
    // Without the ground's forces the same call is the plain forward dynamics.
    VecX<double> qdd_free(d.model.nv());
    generic.accelerations(q.data(), v.data(), tau.data(), qdd_free.data());
    EXPECT_GT((qdd - qdd_free).cwiseAbs().maxCoeff(), 1.0) << "the ground did act";
  }
  EXPECT_GT(pressing, 0);
  EXPECT_GT(apart, 0);  // the tilt lifts the spheres on one side
}

// The ground's forces as the recursion's body forces (contact_forward_dynamics, the generic
// backend's) and as joint forces (contact_joint_forces, the joint-space backends') against an
// independent assembly of the same forces: the explicit 6 x nv Jacobian of each sphere
// (contact_points), the reporting law (contact_law) at its centre and velocity, and
// J^T [f; (w - c) x f]. The accelerations under the assembled joint forces agree with the body
// forces' to 1e-10 relative, and contact_joint_forces' joint forces with the assembled ones.
TEST(GeneratedSimulation, ContactForcesAreJacobianTransposeTimesTheLaw) {
  const gen::Description d = load_lola();
  const std::vector<ContactSphere> spheres = gen::contact_spheres(d);
  sim::GenericBackend<double> generic(d.model, spheres);
  ContactParameters p;
  const GroundPlane ground = GroundPlane::tilted_about_x(0.05);
  double g[kGroundInputs], l[kLawInputs];
  contact_inputs(ground, p, g, l);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-1, 1);
  const VecX<double> q = sunk_into_ground(d, spheres, 1e-3);
  VecX<double> vy(generic.ny()), v(d.model.nv());
  for (int i = 0; i < vy.size(); ++i) vy[i] = 0.3 * unit(rng);
  generic.full_velocities(q.data(), vy.data(), v.data());
  const int nv = d.model.nv(), nc = static_cast<int>(spheres.size());
  const VecX<double> zero = VecX<double>::Zero(nv);
  VecX<double> qdd(nv), out(kContactOutputs * nc);
  generic.accelerations_with_contact(q.data(), v.data(), zero.data(), g, l, qdd.data(), out.data());
  VecX<double> points(3 * nc), jacobians(6 * nv * nc), tau = VecX<double>::Zero(nv);
  generic.contact_points(q.data(), points.data(), jacobians.data());
  int active = 0, pushing = 0;
  for (int k = 0; k < nc; ++k) {
    const Eigen::Map<const Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor>> J(jacobians.data() + 6 * nv * k, 6, nv);
    const Vec3<double> c = points.segment<3>(3 * k), v_c = J.topRows<3>() * v, omega = J.bottomRows<3>() * v;
    const sim::ContactReport<double> r = sim::contact_law<double>(c, v_c, omega, spheres[static_cast<std::size_t>(k)].radius, ground, p);
    EXPECT_NEAR(r.penetration, out[kContactOutputs * k], 1e-15);
    if (!r.active) continue;
    ++active;
    // (a sphere moving out fast enough is active with no force: the Hunt-Crossley clamp)
    EXPECT_LE((r.force - out.segment<3>(kContactOutputs * k + 4)).norm(), 1e-9 * r.force.norm()) << k;
    pushing += r.force.norm() > 1.0;
    tau += J.topRows<3>().transpose() * r.force + J.bottomRows<3>().transpose() * (r.point - c).cross(r.force);
  }
  EXPECT_GT(pushing, 0);
  EXPECT_LT(active, nc);
  VecX<double> qdd_ref(nv);
  generic.accelerations(q.data(), v.data(), tau.data(), qdd_ref.data());
  EXPECT_LT((qdd - qdd_ref).cwiseAbs().maxCoeff(), 1e-10 * qdd_ref.cwiseAbs().maxCoeff());
  Data<double> data(d.model);
  VecX<double> tau_joint = VecX<double>::Zero(nv), out_joint(out.size());
  contact_joint_forces<double>(d.model, data, spheres, p.exponent, q, v.data(), g, l, tau_joint.data(), out_joint.data());
  EXPECT_LT((tau_joint - tau).cwiseAbs().maxCoeff(), 1e-10 * tau.cwiseAbs().maxCoeff());
  EXPECT_LT((out_joint - out).cwiseAbs().maxCoeff(), 1e-12 * out.cwiseAbs().maxCoeff());
}

// A generated backend is built for its scene's exponent: the simulator refuses another, and says
// what to do; a runtime backend takes whichever the options give.
TEST(GeneratedSimulation, AnotherContactExponentIsRefused) {
  sim::SimulatorOptions o;
  o.contact_parameters.exponent = 1.0;
  ASSERT_NE(lola::contact_exponent, 1.0);
  sim::Simulator<lola::Backend> generated(lola::Backend{}, o);
  VecX<double> q = VecX<double>::Zero(lola::nq), v = VecX<double>::Zero(lola::nv);
  q[6] = 1;
  try {
    generated.set_state(q.data(), v.data());
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("built for 1.5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("regenerate"), std::string::npos) << e.what();
  }
  const gen::Description d = load_lola();
  sim::Simulator<sim::GenericBackend<double>> generic(sim::GenericBackend<double>(d.model, gen::contact_spheres(d)), o);
  EXPECT_NO_THROW(generic.set_state(d.assembly.q.data(), v.data()));
}

// A closure that fails says in which sub-system, the generated Newton as the generic one: each of
// Lola's four linkages in turn gets a NaN dependent coordinate (not converged there), and each
// in turn is moved 0.3 rad off (converges; -1); a NaN off the loops blames none (-1).
TEST(GeneratedSimulation, AFailedClosureNamesItsSubSystem) {
  const gen::Description d = load_lola();
  sim::GenericBackend<double> generic(d.model);
  const lola::Backend generated;
  ASSERT_EQ(d.model.subsystems.size(), 4u);
  for (std::size_t k = 0; k < d.model.subsystems.size(); ++k) {
    const int z = d.model.q_index_of_v(d.model.subsystems[k].dependent[0]);
    for (const double change : {std::nan(""), 0.3}) {
      VecX<double> q = d.assembly.q, qg = d.assembly.q;
      q[z] = qg[z] = std::isnan(change) ? change : q[z] + change;
      int sub = -2, sub_g = -2;
      const int status = generic.closure_positions(q.data(), &sub), status_g = generated.closure_positions(qg.data(), &sub_g);
      EXPECT_EQ(status, std::isnan(change) ? 1 : 0) << k;
      EXPECT_EQ(status_g, status) << k;
      EXPECT_EQ(sub, std::isnan(change) ? static_cast<int>(k) : -1) << k;
      EXPECT_EQ(sub_g, sub) << k;
    }
    EXPECT_STREQ(generated.subsystem_name(static_cast<int>(k)), generic.subsystem_name(static_cast<int>(k)));
  }
  // A NaN off the loops (the floating base's x): not converged, and no sub-system to blame.
  VecX<double> q = d.assembly.q, qg = d.assembly.q;
  q[0] = qg[0] = std::nan("");
  int sub = -2, sub_g = -2;
  EXPECT_EQ(generic.closure_positions(q.data(), &sub), 1);
  EXPECT_EQ(generated.closure_positions(qg.data(), &sub_g), 1);
  EXPECT_EQ(sub, -1);
  EXPECT_EQ(sub_g, -1);
}

// One step from Lola standing 0.5 mm deep in the ground (every foot sphere pressing, friction
// acting) with a PD + gravity controller: the generated and generic backends give the same state.
TEST(GeneratedSimulation, OneStepAgreesWithTheGenericBackend) {
  const gen::Description d = load_lola();
  const std::vector<ContactSphere> spheres = gen::contact_spheres(d);
  const VecX<double> q0 = sunk_into_ground(d, spheres, 5e-4);
  VecX<double> v0 = VecX<double>::Zero(d.model.nv());
  v0[0] = 0.05, v0[2] = -0.1, v0[4] = 0.2;  // sliding, sinking and pitching a little
  sim::GenericBackend<double> generic_backend(d.model, spheres);
  VecX<double> vy(generic_backend.ny()), v_full(d.model.nv());
  for (int i = 0; i < generic_backend.ny(); ++i) vy[i] = v0[generic_backend.independent_v_index()[i]];
  generic_backend.full_velocities(q0.data(), vy.data(), v_full.data());
  const int ny = lola::ny;
  const VecX<double> kp = VecX<double>::Constant(ny, 400), kd = VecX<double>::Constant(ny, 20);
  for (Integrator integrator : {Integrator::explicit_euler, Integrator::symplectic_euler, Integrator::rk4,
                                Integrator::dormand_prince45, Integrator::linearly_implicit_euler}) {
    sim::SimulatorOptions o;
    o.integrator = integrator;
    o.step = 1e-4;
    sim::Simulator<sim::GenericBackend<double>> generic(sim::GenericBackend<double>(d.model, spheres), o);
    sim::Simulator<lola::Backend> generated(lola::Backend{}, o);
    generic.set_controller(sim::PdGravityController<sim::GenericBackend<double>>(sim::GenericBackend<double>(d.model), q0, kp, kd));
    generated.set_controller(sim::PdGravityController<lola::Backend>(lola::Backend{}, q0, kp, kd));
    ASSERT_EQ(generic.set_state(q0.data(), v_full.data()), 0);
    ASSERT_EQ(generated.set_state(q0.data(), v_full.data()), 0);
    ASSERT_EQ(generic.step(), StepStatus::ok) << sim::to_string(integrator);
    ASSERT_EQ(generated.step(), StepStatus::ok) << sim::to_string(integrator);
    EXPECT_LT((generic.q() - generated.q()).cwiseAbs().maxCoeff(), 1e-12) << sim::to_string(integrator);
    EXPECT_LT((generic.v() - generated.v()).cwiseAbs().maxCoeff(), 1e-12) << sim::to_string(integrator);
    int active = 0;
    for (const auto& c : generated.contacts()) active += c.active;
    EXPECT_EQ(active, 12);
    EXPECT_LT((generic.control_forces() - generated.control_forces()).cwiseAbs().maxCoeff(), 1e-9);
  }
}

// The four-bar through the generated backend: a free swing of 1 s conserves energy with RK4
// (the loops re-closed every step) as closely as the generic backend does. The projection closes
// to closure_tolerance: by default 1e-11, and Newton then moves the dependent coordinates by about
// that from the end state; at 1e-12 (the closure's own) by less than 1e-12.
TEST(GeneratedSimulation, FourBarSwingConservesEnergy) {
  gen::LoadOptions options;
  options.extras_file = MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.yaml";
  const gen::Description d = gen::load_description(MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.urdf", options);
  for (const double tolerance : {1e-11, 1e-12}) {
    sim::SimulatorOptions o;
    o.step = 1e-3;
    o.closure_tolerance = tolerance;
    sim::Simulator<four_bar::Backend> sim(four_bar::Backend{}, o);
    VecX<double> q = d.assembly.q, v = VecX<double>::Zero(four_bar::nv), vy = VecX<double>::Constant(four_bar::ny, 3.0);
    four_bar::full_velocities(q.data(), vy.data(), v.data());
    ASSERT_EQ(sim.set_state(q.data(), v.data()), 0);
    const double e0 = sim.energy();
    ASSERT_EQ(sim.run_until(1.0), StepStatus::ok);
    EXPECT_LT(std::abs(sim.energy() - e0), 1e-6 * std::abs(e0));
    EXPECT_LT(sim.closure_drift(), 10 * tolerance) << tolerance;
  }
}

}  // namespace
}  // namespace mbgen::test
