// The generated NAME::contact_forward_dynamics_derivatives (the `contact_fd_derivatives` output)
// against the generic contact_forward_dynamics_derivatives (contact_dynamics_derivatives.hpp),
// which test_contact_dynamics_derivatives.cpp checks against dual numbers and central
// differences: double to 1e-12 relative (max-norm over the generic result's), float to 1e-3; no
// allocation. The ground is cut between the spheres' two middle heights at each state
// (compliant_contact_cases.hpp), so that some spheres press, slide or stick and others hang free,
// and the law is the generated one's (its exponent is built in). And the derivatives of a
// simulator step on the generated backend (sim::StepDerivatives<NAME::Backend>, whose stages call
// the generated function) against the same on the generic backend (test_step_derivatives.cpp
// checks those against dual numbers and central differences), 1e-12. Compiled once per robot, as
// test_generated_derivatives.cpp (tests/CMakeLists.txt: mbgen_add_generated_derivatives_test).
#include <gtest/gtest.h>

#include <random>

#include MBGEN_GENERATED_HEADER
#include "collision/contact_spheres.hpp"
#include "compliant_contact_cases.hpp"
#include "derivative_errors.hpp"
#include "malloc_guard.hpp"
#include "mbgen/algorithm/contact_dynamics_derivatives.hpp"
#include "mbgen/sim/step_derivatives.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

namespace robot = MBGEN_GENERATED_NS;

struct Scene {
  Model model;
  CompliantScene contact;
};

Scene load_scene() {
  gen::LoadOptions options;
  options.base = MBGEN_FLOATING ? gen::BaseType::Floating : gen::BaseType::Fixed;
  options.extras_file = MBGEN_EXTRAS;
  const gen::Description d = gen::load_description(MBGEN_DESCRIPTION, options);
  Scene s{d.model, {}};
  s.contact.spheres = gen::contact_spheres(d);
  s.contact.law.exponent = d.scene->contact->parameters.exponent;
  // Soft enough that the forces are of the robot's weight at the cut's depths.
  s.contact.law.stiffness = 1e3;
  s.contact.law.damping = 0.5;
  return s;
}

template <typename T> void check_scalar(double tolerance) {
  Scene s = load_scene();
  const Model& model = s.model;
  ASSERT_TRUE(model.subsystems.empty());
  ASSERT_EQ(model.nv(), robot::nv);
  ASSERT_EQ(static_cast<int>(s.contact.spheres.size()), robot::num_contact_spheres);
  const int n = model.nv(), m = robot::num_contact_spheres;
  const std::size_t nn = static_cast<std::size_t>(n * n);
  Data<double> data(model);
  ContactDynamicsDerivatives<double> d(model);
  std::vector<double> out(static_cast<std::size_t>(kContactOutputs * m));
  std::mt19937_64 rng(9127);
  int pressing = 0, apart = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    // Slow states (every slip below the stiction speed) and fast ones (Coulomb's regime).
    const VecX<double> v = random_vector<double>(n, rng, trial % 2 == 0 ? 2.0 : 1e-3);
    const VecX<double> tau = random_vector<double>(n, rng, 10.0);
    s.contact.cut_at(model, q);
    contact_forward_dynamics_derivatives<double>(model, data, d, s.contact.spheres, s.contact.law.exponent, q, v, tau,
                                                 s.contact.ground_inputs, s.contact.law_inputs, out.data());
    const std::vector<T> qt = as<T>(q), vt = as<T>(v), taut = as<T>(tau);
    std::vector<T> ground(kGroundInputs), law(kLawInputs);
    for (int k = 0; k < kGroundInputs; ++k) ground[static_cast<std::size_t>(k)] = static_cast<T>(s.contact.ground_inputs[k]);
    for (int k = 0; k < kLawInputs; ++k) law[static_cast<std::size_t>(k)] = static_cast<T>(s.contact.law_inputs[k]);
    std::vector<T> a(static_cast<std::size_t>(n)), A(nn), B(nn), C(nn), contacts(out.size());
    robot::contact_forward_dynamics_derivatives(qt.data(), vt.data(), taut.data(), ground.data(), law.data(), a.data(), A.data(),
                                                B.data(), C.data(), contacts.data());
    EXPECT_LT(max_relative(matrix(a, n, 1), d.fd.ddq), tolerance);
    EXPECT_LT(max_relative(matrix(A, n, n), d.fd.dddq_dq), tolerance);
    EXPECT_LT(max_relative(matrix(B, n, n), d.fd.dddq_dv), tolerance);
    EXPECT_LT(max_relative(matrix(C, n, n), d.fd.Minv), tolerance);
    const MatX<double> generic_contacts = Eigen::Map<const MatX<double>>(out.data(), kContactOutputs, m).transpose();
    EXPECT_LT(max_relative(matrix(contacts, m, kContactOutputs), generic_contacts), tolerance);
    for (int k = 0; k < m; ++k) (out[static_cast<std::size_t>(kContactOutputs * k)] > 0 ? pressing : apart) += 1;
    // The ground moved the derivatives: without it they differ (the check is not vacuous).
    DynamicsDerivatives<double> free(model);
    forward_dynamics_derivatives<double>(model, data, free, q, v, tau);
    EXPECT_GT((free.dddq_dv - d.fd.dddq_dv).cwiseAbs().maxCoeff(), 1e-6 * d.fd.dddq_dv.cwiseAbs().maxCoeff());
  }
  EXPECT_GT(pressing, 0);
  EXPECT_GT(apart, 0);
}

TEST(GeneratedContactDerivatives, DoubleEqualsGeneric) { check_scalar<double>(1e-12); }
TEST(GeneratedContactDerivatives, FloatEqualsGeneric) { check_scalar<float>(1e-3); }

TEST(GeneratedContactDerivatives, StepDerivativesOnTheGeneratedBackendEqualTheGenerics) {
  Scene s = load_scene();
  const Model& model = s.model;
  std::mt19937_64 rng(3301);
  for (const sim::Integrator integrator : {sim::Integrator::rk4, sim::Integrator::symplectic_euler}) {
    for (int trial = 0; trial < 3; ++trial) {
      const VecX<double> q = random_configuration<double>(model, rng);
      const VecX<double> v = random_vector<double>(model.nv(), rng, 1.0);
      const VecX<double> tau = random_vector<double>(model.nv(), rng, 10.0);
      s.contact.cut_at(model, q);
      sim::SimulatorOptions o;
      o.integrator = integrator;
      o.ground = s.contact.ground;
      o.contact_parameters = s.contact.law;
      o.energy_check_interval = 0;
      sim::Simulator<robot::Backend> generated(robot::Backend{}, o);
      sim::Simulator<sim::GenericBackend<double>> generic(sim::GenericBackend<double>(model, s.contact.spheres), o);
      generated.set_state(q.data(), v.data());
      generic.set_state(q.data(), v.data());
      sim::StepDerivatives<robot::Backend> dg(generated);
      sim::StepDerivatives<sim::GenericBackend<double>> dd(generic);
      dg.compute(q.data(), v.data(), tau.data());
      dd.compute(q.data(), v.data(), tau.data());
      EXPECT_LT(max_relative(dg.q_next(), dd.q_next()), 1e-12) << to_string(integrator);
      EXPECT_LT(max_relative(dg.v_next(), dd.v_next()), 1e-12) << to_string(integrator);
      EXPECT_LT(max_relative(dg.dx_dx(), dd.dx_dx()), 1e-12) << to_string(integrator);
      EXPECT_LT(max_relative(dg.dx_du(), dd.dx_du()), 1e-12) << to_string(integrator);
      // The ground acts in the step (its derivative is not the free fall's).
      bool pressing = false;
      for (int k = 0; k < robot::num_contact_spheres; ++k)
        pressing = pressing || dg.contact_outputs()[static_cast<std::size_t>(kContactOutputs * k)] > 0;
      EXPECT_TRUE(pressing);
    }
  }
}

TEST(GeneratedContactDerivatives, AllocateNothing) {
  const std::size_t n = robot::nv, m = robot::num_contact_spheres;
  std::vector<double> q(robot::nq, 0.0), v(n, 0.5), a(n), A(n * n), B(A), C(A), contacts(kContactOutputs * m);
  if (MBGEN_FLOATING) q[6] = 1;  // the base's quaternion w
  const double ground[kGroundInputs] = {0, 0, 1, 10.0};  // every sphere deep below the plane
  const double law[kLawInputs] = {1e3, 0.5, 0.8, 0.01};
  MallocGuard guard;
  robot::contact_forward_dynamics_derivatives(q.data(), v.data(), v.data(), ground, law, a.data(), A.data(), B.data(), C.data(),
                                              contacts.data());
  EXPECT_EQ(guard.count(), 0u);
  EXPECT_TRUE(std::isfinite(A[0]) && std::isfinite(C[0]) && contacts[0] > 0);
}

}  // namespace
}  // namespace mbgen::test
