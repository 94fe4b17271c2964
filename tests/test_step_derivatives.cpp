// The derivatives of one simulator step (runtime/include/mbgen/sim/step_derivatives.hpp) on every
// URDF of the suite, fixed and floating, for explicit Euler, symplectic Euler and RK4, with the
// compliant ground of compliant_contact_cases.hpp (half the spheres in contact) and one joint
// pushed 0.02 past its range (its end stop acting):
//  - the values are the simulator's own step (Simulator<GenericBackend<double>>), 1e-12 (or eps
//    cond(M): the simulator takes the ground as body forces);
//  - the Jacobians equal forward-mode dual numbers pushed through a reference step written here
//    (stages of contact_forward_dynamics, the articulated-body contact formulation, with the
//    stops' torques and the configuration rate; the output read in the tangent at q+), to 1e-10
//    relative (or 10 eps cond(M)), and the step is not the identity;
//  - central differences through the simulator's step along integrate / difference, 1e-6;
// and compute() allocates nothing; closed loops and the integrators not differentiated are refused.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <memory>
#include <random>
#include <tuple>

#include "autodiff_reference.hpp"
#include "compliant_contact_cases.hpp"
#include "malloc_guard.hpp"
#include "mbgen/sim/step_derivatives.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

using sim::Integrator;
using sim::Simulator;
// The generic backend's; test_generated_contact_derivatives.cpp compares a generated backend's with it.
using GenericStepDerivatives = sim::StepDerivatives<sim::GenericBackend<double>>;
using Backend = sim::GenericBackend<double>;

constexpr double kStep = 1e-4;  // s: the simulator's default

double condition_number(const MatX<double>& M) {
  const VecX<double> s = Eigen::JacobiSVD<MatX<double>>(M).singularValues();
  return s[0] / s[s.size() - 1];
}

/// The tangent at q+ (unit quaternion) of a dual configuration's derivative part: a 1-DoF joint's
/// own, a floating base's R^T dp and 2 vec(conj(quat) * dquat) (the inverse of
/// seeded_configuration_along).
VecX<double> tangent_part(const Model& model, const VecX<Dual>& q) {
  VecX<double> out(model.nv());
  const VecX<double> d = derivative_part(q);
  int j = 0, k = 0;
  if (model.floating_base()) {
    const double x = q[3].value(), y = q[4].value(), z = q[5].value(), w = q[6].value();
    out.head<3>() = quaternion_to_rotation<double>(x, y, z, w).transpose() * d.head<3>();
    const Eigen::Quaterniond conj(w, -x, -y, -z), dq(d[6], d[3], d[4], d[5]);
    out.segment<3>(3) = 2 * (conj * dq).vec();
    j = 7, k = 6;
  }
  for (; j < model.nq(); ++j, ++k) out[k] = d[j];
  return out;
}

using Case = std::tuple<UrdfCase, Integrator>;

class StepDerivativesTest : public ::testing::TestWithParam<Case> {
 protected:
  void SetUp() override {
    const UrdfCase& c = std::get<0>(GetParam());
    model = load_tree(c.path, c.base);
    std::mt19937_64 rng(71);
    scene = leaf_spheres(model, rng);
    q = random_configuration<double>(model, rng);
    v = random_vector<double>(model.nv(), rng, 0.5);
    tau = random_vector<double>(model.nv(), rng, 10.0);
    Backend probe(model);
    if (probe.num_limited_joints() > 0) q[probe.limited_q_index()[0]] = probe.limited_upper()[0] + 0.02;
    scene.cut_at(model, q);
    options.integrator = std::get<1>(GetParam());
    if (probe.num_limited_joints() > 0) {
      // The stop's stiffness and damping fixed here, not from the start pose's inertia (the central
      // differences start from other poses): 20 Hz on the inertia it feels at q, 1 s/rad, no cap.
      Simulator<Backend> at_q(Backend(model), options);
      const VecX<double> rest = VecX<double>::Zero(model.nv());
      at_q.set_state(q.data(), rest.data());
      const double inertia = at_q.joint_stops()[0].inertia, omega = 2 * M_PI * 20;
      options.joint_stops.joints.push_back({probe.limited_joint_name(0), false, inertia * omega * omega, 1.0});
      options.joint_stops.max_damping_ratio = 0;
    }
    // robot_delta's ball-joint stand-ins weigh 6.5 mg with 1.6e-11 kg m^2: a sphere 5 cm off one
    // feels 7e-9 kg, a contact frequency of 1.5e5 rad/s that a 1e-4 s step does not resolve (RK4
    // grows the state 1e25-fold in one step). Its step is 1e-6 s.
    options.step = short_name(c.path).find("robot_delta") != std::string::npos ? 1e-6 : kStep;
    options.control_period = 0;
    options.energy_check_interval = 0;
    options.max_penetration = 1;
    options.ground = scene.ground;
    options.contact_parameters = scene.law;
  }
  /// A simulator at (q0, v0) whose controller holds tau.
  std::unique_ptr<Simulator<Backend>> simulator(const VecX<double>& q0, const VecX<double>& v0) {
    auto s = std::make_unique<Simulator<Backend>>(Backend(model, scene.spheres), options);
    s->set_controller([this](double, const double*, const double*, double* t) { Eigen::Map<VecX<double>>(t, model.nv()) = tau; });
    if (passive) s->set_passive_forces(passive);
    s->set_state(q0.data(), v0.data());
    return s;
  }

  /// The step's Jacobians by central differences through the simulator (dq along integrate, the
  /// result's dq+ by difference from d's q+), and the tolerances they are compared at.
  void central_differences(const GenericStepDerivatives& d, MatX<double>& dx_dx, MatX<double>& dx_du, double& tol_x,
                           double& tol_u) {
    const int nv = model.nv();
    const auto step_from = [&](const VecX<double>& qx, const VecX<double>& vx, const VecX<double>& ux, VecX<double>& q1,
                               VecX<double>& v1) {
      const VecX<double> held = tau;
      tau = ux;
      auto t = simulator(qx, vx);
      EXPECT_EQ(t->step(), sim::StepStatus::ok);
      tau = held;
      q1 = t->q(), v1 = t->v();
    };
    dx_dx.resize(2 * nv, 2 * nv), dx_du.resize(2 * nv, nv);
    VecX<double> qp, vp, qm, vm, dq(nv), dq_minus(nv);
    const auto column = [&](const VecX<double>& qa, const VecX<double>& va, const VecX<double>& ua, const VecX<double>& qb,
                            const VecX<double>& vb, const VecX<double>& ub, double h) {
      step_from(qa, va, ua, qp, vp);
      step_from(qb, vb, ub, qm, vm);
      difference<double>(model, d.q_next(), qp, dq);
      difference<double>(model, d.q_next(), qm, dq_minus);
      VecX<double> c(2 * nv);
      c << (dq - dq_minus) / (2 * h), (vp - vm) / (2 * h);
      return c;
    };
    const double h = 1e-6, hv = 1e-5, hu = 1e-4;
    for (int k = 0; k < nv; ++k) {
      const VecX<double> e = VecX<double>::Unit(nv, k);
      const CentralPair p = central_pair(model, q, e, h);
      dx_dx.col(k) = column(p.plus, v, tau, p.minus, v, tau, h);
      dx_dx.col(nv + k) = column(q, v + hv * e, tau, q, v - hv * e, tau, hv);
      dx_du.col(k) = column(q, v, tau + hu * e, q, v, tau - hu * e, hu);
    }
    Data<double> other(model);
    const double condition = condition_number(crba<double>(model, other, q));
    tol_x = std::max(1e-6, 2.2e-16 * condition / h);
    tol_u = std::max(1e-6, 2.2e-16 * condition / hu);
  }

  /// d's Jacobians equal the central differences (their dx_dx and its tolerance returned).
  void expect_central_differences(const GenericStepDerivatives& d, MatX<double>& dx_dx, double& tol_x) {
    MatX<double> dx_du;
    double tol_u;
    central_differences(d, dx_dx, dx_du, tol_x, tol_u);
    EXPECT_LT(relative_error(d.dx_dx(), dx_dx), tol_x);
    EXPECT_LT(relative_error(d.dx_du(), dx_du), tol_u);
  }

  /// The reference step in dual numbers: stage by stage as the simulator, the ground on the
  /// spheres in contact at the stage's value (zero force near it otherwise).
  void dual_step(sim::JointStops<Dual>& stops, const VecX<Dual>& q0, const VecX<Dual>& v0, const VecX<Dual>& u, VecX<Dual>& q1,
                 VecX<Dual>& v1) const {
    const bool fb = model.floating_base();
    const int nq = model.nq(), nv = model.nv();
    Data<Dual> data(model);
    Data<double> values(model);
    const auto f = [&](const VecX<Dual>& q, const VecX<Dual>& v, VecX<Dual>& qdot, VecX<Dual>& vdot) {
      VecX<Dual> qhat = q;
      sim::normalize_quaternion<Dual>(fb, qhat.data());
      VecX<Dual> t = u;
      stops.add_torques(qhat.data(), v.data(), t.data(), false);
      VecX<double> qv(nq), vv(nv), tv(nv);
      for (int i = 0; i < nq; ++i) qv[i] = qhat[i].value();
      for (int i = 0; i < nv; ++i) vv[i] = v[i].value(), tv[i] = t[i].value();
      std::vector<double> out(kContactOutputs * scene.spheres.size());
      contact_forward_dynamics<double>(model, values, scene.spheres, scene.law.exponent, qv, vv, tv, scene.ground_inputs,
                                       scene.law_inputs, out.data());
      std::vector<ContactSphere> touching;
      for (std::size_t k = 0; k < scene.spheres.size(); ++k)
        if (out[kContactOutputs * k] > 0) touching.push_back(scene.spheres[k]);
      Dual ground[kGroundInputs], law[kLawInputs];
      for (int i = 0; i < kGroundInputs; ++i) ground[i] = Dual(scene.ground_inputs[i]);
      for (int i = 0; i < kLawInputs; ++i) law[i] = Dual(scene.law_inputs[i]);
      std::vector<Dual> dual_out(kContactOutputs * touching.size());
      vdot = contact_forward_dynamics<Dual>(model, data, touching, scene.law.exponent, qhat, v, t, ground, law, dual_out.data());
      qdot.resize(nq);
      sim::configuration_rate<Dual>(fb, nq, qhat.data(), v.data(), qdot.data());
    };
    const double h = options.step;
    VecX<Dual> kq[4], kv[4];
    f(q0, v0, kq[0], kv[0]);
    switch (options.integrator) {
      case Integrator::explicit_euler:
        q1 = q0 + Dual(h) * kq[0], v1 = v0 + Dual(h) * kv[0];
        break;
      case Integrator::symplectic_euler:
        v1 = v0 + Dual(h) * kv[0];
        q1.resize(nq);
        sim::configuration_rate<Dual>(fb, nq, q0.data(), v1.data(), q1.data());
        q1 = q0 + Dual(h) * q1;
        break;
      default: {
        f(q0 + Dual(h / 2) * kq[0], v0 + Dual(h / 2) * kv[0], kq[1], kv[1]);
        f(q0 + Dual(h / 2) * kq[1], v0 + Dual(h / 2) * kv[1], kq[2], kv[2]);
        f(q0 + Dual(h) * kq[2], v0 + Dual(h) * kv[2], kq[3], kv[3]);
        q1 = q0 + Dual(h / 6) * (kq[0] + Dual(2) * kq[1] + Dual(2) * kq[2] + kq[3]);
        v1 = v0 + Dual(h / 6) * (kv[0] + Dual(2) * kv[1] + Dual(2) * kv[2] + kv[3]);
      }
    }
    sim::normalize_quaternion<Dual>(fb, q1.data());
  }

  Model model;
  CompliantScene scene;
  VecX<double> q, v, tau;
  sim::SimulatorOptions options;
  Simulator<Backend>::PassiveForces passive;  ///< none unless a test sets them
};

TEST_P(StepDerivativesTest, ValuesAreTheSimulatorsStep) {
  auto s = simulator(q, v);
  GenericStepDerivatives d(*s);
  d.compute(q.data(), v.data(), tau.data());
  ASSERT_EQ(s->step(), sim::StepStatus::ok);
  EXPECT_DOUBLE_EQ(s->time(), options.step);
  // The simulator's accelerations take the ground as body forces, these as joint forces: the two
  // agree to eps cond(M).
  Data<double> other(model);
  const double tolerance = std::max(1e-12, 2.2e-16 * condition_number(crba<double>(model, other, q)));
  EXPECT_LT(relative_error(d.q_next(), s->q()), tolerance);
  EXPECT_LT(relative_error(d.v_next(), s->v()), tolerance);
}

TEST_P(StepDerivativesTest, MatchDualNumbers) {
  auto s = simulator(q, v);
  // The scene acts: spheres in contact and, where the robot has a range, its stop.
  int active = 0;
  for (const auto& c : s->contacts()) active += c.force.norm() > 0 ? 1 : 0;
  ASSERT_GT(active, 0);
  Backend probe(model);
  if (probe.num_limited_joints() > 0) {
    ASSERT_TRUE(s->joint_stops()[0].active);
  }
  GenericStepDerivatives d(*s);
  d.compute(q.data(), v.data(), tau.data());

  sim::JointStops<Dual> stops;
  stops.configure(s->backend(), options.joint_stops);
  for (int k = 0; k < stops.size(); ++k) stops.set_inertia(k, s->joint_stops()[static_cast<std::size_t>(k)].inertia);
  const int nv = model.nv();
  MatX<double> dx_dx(2 * nv, 2 * nv), dx_du(2 * nv, nv);
  VecX<Dual> q1, v1;
  const auto column = [&](const VecX<Dual>& qx, const VecX<Dual>& vx, const VecX<Dual>& ux) {
    dual_step(stops, qx, vx, ux, q1, v1);
    VecX<double> c(2 * nv);
    c << tangent_part(model, q1), derivative_part(v1);
    return c;
  };
  const VecX<Dual> unseeded_q = seeded_configuration_along(model, q, VecX<double>::Zero(nv));
  for (int k = 0; k < nv; ++k) {
    dx_dx.col(k) = column(seeded_configuration(model, q, k), seeded_vector(v), seeded_vector(tau));
    dx_dx.col(nv + k) = column(unseeded_q, seeded_vector(v, k), seeded_vector(tau));
    dx_du.col(k) = column(unseeded_q, seeded_vector(v), seeded_vector(tau, k));
  }
  Data<double> other(model);
  const double condition = condition_number(crba<double>(model, other, q)), tolerance = std::max(1e-10, 10 * 2.2e-16 * condition);
  SCOPED_TRACE(std::to_string(active) + " spheres in contact, condition number " + std::to_string(condition));
  EXPECT_LT(relative_error(d.dx_dx(), dx_dx), tolerance);
  EXPECT_LT(relative_error(d.dx_du(), dx_du), tolerance);
  // Not the identity: the step moves the state by more than the tolerance.
  EXPECT_GT(relative_error(MatX<double>::Identity(2 * nv, 2 * nv), dx_dx), 100 * tolerance);
}

TEST_P(StepDerivativesTest, MatchCentralDifferencesThroughTheSimulator) {
  auto s = simulator(q, v);
  GenericStepDerivatives d(*s);
  d.compute(q.data(), v.data(), tau.data());
  MatX<double> dx_dx;
  double tol_x;
  expect_central_differences(d, dx_dx, tol_x);
}

// Passive forces (Simulator::set_passive_forces) with their Jacobians given: a spring to 0.1 and a
// damper on every 1-DoF joint, and a damper coupling each to the next (so the law is not
// diagonal), against central differences through the simulator that applies them. RK4 only (the
// stage composition is the integrators' common code, checked for all three above), on the real
// robots of the suite: the parallel_legs stand-ins' milligram links would make the spring a
// frequency no step resolves.
class StepDerivativesPassiveTest : public StepDerivativesTest {};

TEST_P(StepDerivativesPassiveTest, WithTheirJacobiansMatchCentralDifferences) {
  const int nv = model.nv(), first = model.floating_base() ? 6 : 0;
  const double k = 40, c = 0.7, coupling = 0.2;
  const int base_q = model.floating_base() ? 7 : 0;
  passive = [=](const double* qx, const double* vx, double* t) {
    for (int i = first; i < nv; ++i) {
      t[i] += -k * (qx[base_q + i - first] - 0.1) - c * vx[i];
      if (i + 1 < nv) t[i] += -coupling * vx[i + 1];
    }
  };
  const GenericStepDerivatives::PassiveDerivatives jacobians = [=](const double*, const double*, double* dq, double* dv) {
    for (int i = 0; i < nv * nv; ++i) dq[i] = dv[i] = 0;
    for (int i = first; i < nv; ++i) {
      dq[i * nv + i] = -k;
      dv[i * nv + i] = -c;
      if (i + 1 < nv) dv[i * nv + i + 1] = -coupling;
    }
  };
  auto s = simulator(q, v);
  GenericStepDerivatives d(*s, jacobians);
  d.compute(q.data(), v.data(), tau.data());
  MatX<double> dx_dx;
  double tol_x;
  expect_central_differences(d, dx_dx, tol_x);
  // The law is felt: the same step without it differs by far more than the tolerance.
  passive = {};
  auto bare = simulator(q, v);
  GenericStepDerivatives without(*bare);
  without.compute(q.data(), v.data(), tau.data());
  EXPECT_GT(relative_error(without.dx_dx(), dx_dx), 100 * tol_x);
}


TEST_P(StepDerivativesTest, AllocatesNothing) {
  auto s = simulator(q, v);
  GenericStepDerivatives d(*s);
  MallocGuard guard;
  d.compute(q.data(), v.data(), tau.data());
  EXPECT_EQ(guard.count(), 0u);
}

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const UrdfCase& c : all_urdf_cases())
    for (Integrator i : {Integrator::explicit_euler, Integrator::symplectic_euler, Integrator::rk4}) out.emplace_back(c, i);
  return out;
}
std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return urdf_case_name(::testing::TestParamInfo<UrdfCase>(std::get<0>(info.param), info.index)) + "_" +
         sim::to_string(std::get<1>(info.param));
}
INSTANTIATE_TEST_SUITE_P(AllUrdfs, StepDerivativesTest, ::testing::ValuesIn(cases()), case_name);

std::vector<Case> passive_cases() {
  std::vector<Case> out;
  for (const UrdfCase& c : all_urdf_cases())
    if (c.path.find("parallel_legs") == std::string::npos) out.emplace_back(c, Integrator::rk4);
  return out;
}
INSTANTIATE_TEST_SUITE_P(RealRobots, StepDerivativesPassiveTest, ::testing::ValuesIn(passive_cases()), case_name);

TEST(StepDerivativesRefusals, PassiveForcesWithoutTheirJacobians) {
  const Model tree = load_tree(shared_robot("iiwa14/iiwa14_primitive_collision.urdf"), gen::BaseType::Fixed);
  Simulator<Backend> s{Backend(tree)};
  s.set_passive_forces([](const double*, const double* v, double* t) { t[0] -= 0.5 * v[0]; });
  const VecX<double> q0 = neutral_configuration<double>(tree), v0 = VecX<double>::Zero(tree.nv());
  s.set_state(q0.data(), v0.data());
  try {
    GenericStepDerivatives d(s);
    ADD_FAILURE() << "passive forces without Jacobians accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("give their Jacobians"), std::string::npos) << e.what();
  }
  Simulator<Backend> plain{Backend(tree)};
  plain.set_state(q0.data(), v0.data());
  EXPECT_THROW(GenericStepDerivatives(plain, [](const double*, const double*, double*, double*) {}), std::invalid_argument);
}

// What is not differentiated is refused, with what to do.
TEST(StepDerivativesRefusals, ClosedLoopsAndOtherIntegrators) {
  const gen::Description four_bar = load_loop_case({"four_bar", MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.urdf",
                                                    MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.yaml"});
  Simulator<Backend> closed{Backend(four_bar.model)};
  const VecX<double> qc = neutral_configuration<double>(four_bar.model), vc = VecX<double>::Zero(four_bar.model.nv());
  closed.set_state(qc.data(), vc.data());
  try {
    GenericStepDerivatives d(closed);
    ADD_FAILURE() << "closed loops accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("closed loops"), std::string::npos) << e.what();
  }
  // The backend's own derivatives are a tree's: called on the closed model, an error naming it.
  std::vector<double> x(static_cast<std::size_t>(four_bar.model.nv())), m(x.size() * x.size());
  const double ground[kGroundInputs] = {0, 0, 1, 0}, law[kLawInputs] = {1e3, 0.5, 0.8, 0.01};
  try {
    closed.backend().contact_dynamics_derivatives(qc.data(), vc.data(), vc.data(), ground, law, x.data(), m.data(), m.data(),
                                                  m.data(), nullptr);
    ADD_FAILURE() << "closed loops differentiated";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("closed loops"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(four_bar.model.name), std::string::npos) << e.what();
  }
  const Model tree = load_tree(shared_robot("iiwa14/iiwa14_primitive_collision.urdf"), gen::BaseType::Fixed);
  for (Integrator i : {Integrator::dormand_prince45, Integrator::linearly_implicit_euler}) {
    sim::SimulatorOptions o;
    o.integrator = i;
    Simulator<Backend> s{Backend(tree), o};
    const VecX<double> q0 = neutral_configuration<double>(tree), v0 = VecX<double>::Zero(tree.nv());
    s.set_state(q0.data(), v0.data());
    try {
      GenericStepDerivatives d(s);
      ADD_FAILURE() << sim::to_string(i) << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(sim::to_string(i)), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace mbgen::test
