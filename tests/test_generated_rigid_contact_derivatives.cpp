// The generated NAME::rigid_contact_forward_dynamics_derivatives (the `rigid_contact_fd_derivatives`
// output) against the generic rigid_contact_dynamics_derivatives (rigid_contact_derivatives.hpp),
// which test_rigid_contact_derivatives.cpp checks against dual numbers and central differences:
// the accelerations, the contact forces, their six derivative blocks and the operator's pivots,
// double to 1e-12 relative (max-norm over the generic result's), float to 1e-3; the status the
// pivots give equals the generic one's; no allocation. The contacts are the extras' `scene:
// rigid_contacts` (a frame and two points: both kinds of rows). Compiled once per robot
// (tests/CMakeLists.txt: mbgen_add_generated_derivatives_test). MBGEN_DERIVATIVES_Q_TAU: the robot was
// generated with `derivatives_wrt: [q, tau]`, its function without the v blocks (dqdd/dv and
// dlambda/dv); the blocks it has are checked the same way.
#include <gtest/gtest.h>

#include <random>

#include MBGEN_GENERATED_HEADER
#include "derivative_errors.hpp"
#include "malloc_guard.hpp"
#include "mbgen/algorithm/rigid_contact_derivatives.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

namespace robot = MBGEN_GENERATED_NS;

struct Scene {
  Model model;
  std::vector<RigidContact> contacts;
};

Scene load_scene() {
  gen::LoadOptions options;
  options.base = MBGEN_FLOATING ? gen::BaseType::Floating : gen::BaseType::Fixed;
  options.extras_file = MBGEN_EXTRAS;
  const gen::Description d = gen::load_description(MBGEN_DESCRIPTION, options);
  Scene s{d.model, {}};
  for (const gen::RigidContactSpec& c : d.scene->rigid_contacts)
    s.contacts.push_back({d.model.frame_index(c.frame), c.kind == "point" ? RigidContactKind::Point : RigidContactKind::Frame});
  return s;
}

template <typename T> void check_scalar(double tolerance) {
  Scene s = load_scene();
  const Model& model = s.model;
  ASSERT_EQ(model.nv(), robot::nv);
  Data<double> data(model);
  RigidContactWorkspace<double> ws(model, s.contacts);
  RigidContactDerivatives<double> d(model, ws);
  const int n = model.nv(), m = ws.m;
  ASSERT_EQ(m, 12);  // the extras' frame and two points
  const std::size_t nn = static_cast<std::size_t>(n * n), mn = static_cast<std::size_t>(m * n);
  std::mt19937_64 rng(4471);
  for (int trial = 0; trial < 6; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    const VecX<double> v = random_vector<double>(n, rng, 1.0);
    const VecX<double> tau = random_vector<double>(n, rng, 10.0);
    rigid_contact_dynamics_derivatives<double>(model, data, ws, d, q, v, tau);
    ASSERT_EQ(ws.status, RigidContactStatus::Solved);
    const std::vector<T> qt = as<T>(q), vt = as<T>(v), taut = as<T>(tau);
    std::vector<T> a(static_cast<std::size_t>(n)), lambda(static_cast<std::size_t>(m)), A(nn), B(nn), C(nn), LA(mn), LB(mn),
        LC(mn), pivots(static_cast<std::size_t>(2 * m));
#if MBGEN_DERIVATIVES_Q_TAU
    robot::rigid_contact_forward_dynamics_derivatives(qt.data(), vt.data(), taut.data(), a.data(), lambda.data(), A.data(),
                                                      LA.data(), C.data(), LC.data(), pivots.data());
#else
    robot::rigid_contact_forward_dynamics_derivatives(qt.data(), vt.data(), taut.data(), a.data(), lambda.data(), A.data(),
                                                      LA.data(), B.data(), LB.data(), C.data(), LC.data(), pivots.data());
    EXPECT_LT(max_relative(matrix(B, n, n), d.da_dv), tolerance);
    EXPECT_LT(max_relative(matrix(LB, m, n), d.dlambda_dv), tolerance);
#endif
    EXPECT_LT(max_relative(matrix(a, n, 1), ws.a), tolerance);
    EXPECT_LT(max_relative(matrix(lambda, m, 1), ws.lambda), tolerance);
    EXPECT_LT(max_relative(matrix(A, n, n), d.da_dq), tolerance);
    EXPECT_LT(max_relative(matrix(C, n, n), d.da_dtau), tolerance);
    EXPECT_LT(max_relative(matrix(LA, m, n), d.dlambda_dq), tolerance);
    EXPECT_LT(max_relative(matrix(LC, m, n), d.dlambda_dtau), tolerance);
    const MatX<double> P = matrix(pivots, m, 2);
    EXPECT_LT(max_relative(P.col(0), ws.operator_diagonal), tolerance);
    EXPECT_LT(max_relative(P.col(1), ws.JY_factor.diagonal().cwiseInverse()), tolerance);
    EXPECT_EQ(rigid_contact_operator_status<double>(P.col(0), P.col(1), m, ws.singular_tolerance), ws.status);
    // The contacts moved the derivatives: without them they differ (the check is not vacuous).
    DynamicsDerivatives<double> free(model);
    forward_dynamics_derivatives<double>(model, data, free, q, v, tau);
    EXPECT_GT((free.dddq_dq - d.da_dq).cwiseAbs().maxCoeff(), 1e-6 * d.da_dq.cwiseAbs().maxCoeff());
  }
}

TEST(GeneratedRigidContactDerivatives, DoubleEqualsGeneric) { check_scalar<double>(1e-12); }
TEST(GeneratedRigidContactDerivatives, FloatEqualsGeneric) { check_scalar<float>(1e-3); }

// The pivots tell a dependent set of rows: the status rule applied to them says Singular when one
// pivot is negligible (the rule is the generic one's; the generated pivots equal the generic's above).
TEST(GeneratedRigidContactDerivatives, PivotsTellASingularOperator) {
  const double diagonal[3] = {2.0, 1.0, 3.0}, regular[3] = {2.0, 0.5, 1.0}, dependent[3] = {2.0, 1e-13, 1.0};
  EXPECT_EQ(rigid_contact_operator_status<double>(diagonal, regular, 3, 1e-12), RigidContactStatus::Solved);
  EXPECT_EQ(rigid_contact_operator_status<double>(diagonal, dependent, 3, 1e-12), RigidContactStatus::Singular);
}

TEST(GeneratedRigidContactDerivatives, AllocatesNothing) {
  const std::size_t n = robot::nv, m = 12;
  std::vector<double> q(robot::nq, 0.0), v(n, 0.5), a(n), lambda(m), A(n * n), B(A), C(A), LA(m * n), LB(LA), LC(LA),
      pivots(2 * m);
  if (MBGEN_FLOATING) q[6] = 1;  // the base's quaternion w
  MallocGuard guard;
#if MBGEN_DERIVATIVES_Q_TAU
  robot::rigid_contact_forward_dynamics_derivatives(q.data(), v.data(), v.data(), a.data(), lambda.data(), A.data(), LA.data(),
                                                    C.data(), LC.data(), pivots.data());
#else
  robot::rigid_contact_forward_dynamics_derivatives(q.data(), v.data(), v.data(), a.data(), lambda.data(), A.data(), LA.data(),
                                                    B.data(), LB.data(), C.data(), LC.data(), pivots.data());
#endif
  EXPECT_EQ(guard.count(), 0u);
  EXPECT_TRUE(std::isfinite(A[0]) && std::isfinite(LC[0]) && pivots[1] > 0);
}

}  // namespace
}  // namespace mbgen::test
