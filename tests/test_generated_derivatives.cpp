// Generated derivatives (NAME::inverse_dynamics_derivatives, NAME::forward_dynamics_derivatives)
// against the generic runtime's (rnea_derivatives.hpp, aba_derivatives.hpp), which
// test_rnea_derivatives.cpp checks against dual numbers: double to 1e-12 relative (max-norm over
// the generic result's max-norm), float to 1e-3 (single precision through ~10^4 operations, the
// forward derivatives through a solve with the mass matrix); no allocation. Compiled once per
// robot with MBGEN_GENERATED_HEADER, MBGEN_GENERATED_NS, MBGEN_DESCRIPTION, MBGEN_EXTRAS (empty:
// none) and MBGEN_FLOATING defined (tests/CMakeLists.txt: mbgen_add_generated_derivatives_test).
// MBGEN_DERIVATIVES_Q_TAU: the robot was generated with `derivatives_wrt: [q, tau]`, its functions
// without the dtau/dv and dqdd/dv blocks; the blocks it has are checked the same way.
#include <gtest/gtest.h>

#include <random>

#include MBGEN_GENERATED_HEADER
#include "derivative_errors.hpp"
#include "malloc_guard.hpp"
#include "mbgen/algorithm/aba_derivatives.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

namespace robot = MBGEN_GENERATED_NS;

Model load_tree_model() {
  gen::LoadOptions options;
  options.base = MBGEN_FLOATING ? gen::BaseType::Floating : gen::BaseType::Fixed;
  if (std::string(MBGEN_EXTRAS).size() > 0) options.extras_file = MBGEN_EXTRAS;
  Model m = gen::load_description(MBGEN_DESCRIPTION, options).model;
  m.closures.clear();
  m.subsystems.clear();
  m.update_structure();
  return m;
}

template <typename T> VecX<double> vec(const std::vector<T>& x) {
  VecX<double> out(static_cast<int>(x.size()));
  for (std::size_t k = 0; k < x.size(); ++k) out[static_cast<int>(k)] = static_cast<double>(x[k]);
  return out;
}

template <typename T> void check_scalar(double tolerance) {
  const Model model = load_tree_model();
  ASSERT_EQ(model.nv(), robot::nv);
  ASSERT_EQ(model.nq(), robot::nq);
  const int n = model.nv();
  const std::size_t nn = static_cast<std::size_t>(n * n);
  Data<double> data(model);
  DynamicsDerivatives<double> d(model);
  std::mt19937_64 rng(541);
  for (int trial = 0; trial < 5; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    const VecX<double> v = random_vector<double>(n, rng, 2.0);
    const VecX<double> a = random_vector<double>(n, rng, 5.0);
    const VecX<double> tau = random_vector<double>(n, rng, 10.0);
    const std::vector<T> qt = as<T>(q), vt = as<T>(v), at = as<T>(a), taut = as<T>(tau);
    std::vector<T> x(static_cast<std::size_t>(n)), A(nn), B(nn), C(nn);

    inverse_dynamics_derivatives<double>(model, data, d, q, v, a);
#if MBGEN_DERIVATIVES_Q_TAU
    robot::inverse_dynamics_derivatives(qt.data(), vt.data(), at.data(), x.data(), A.data());
#else
    robot::inverse_dynamics_derivatives(qt.data(), vt.data(), at.data(), x.data(), A.data(), B.data());
    EXPECT_LT(max_relative(matrix(B, n, n), d.dtau_dv), tolerance);
#endif
    EXPECT_LT(relative_error(vec(x), d.tau), tolerance);
    EXPECT_LT(max_relative(matrix(A, n, n), d.dtau_dq), tolerance);

    forward_dynamics_derivatives<double>(model, data, d, q, v, tau);
#if MBGEN_DERIVATIVES_Q_TAU
    robot::forward_dynamics_derivatives(qt.data(), vt.data(), taut.data(), x.data(), A.data(), C.data());
#else
    robot::forward_dynamics_derivatives(qt.data(), vt.data(), taut.data(), x.data(), A.data(), B.data(), C.data());
    EXPECT_LT(max_relative(matrix(B, n, n), d.dddq_dv), tolerance);
#endif
    EXPECT_LT(relative_error(vec(x), d.ddq), tolerance);
    EXPECT_LT(max_relative(matrix(A, n, n), d.dddq_dq), tolerance);
    EXPECT_LT(max_relative(matrix(C, n, n), d.Minv), tolerance);
  }
}

TEST(GeneratedDerivatives, DoubleEqualsGeneric) { check_scalar<double>(1e-12); }
TEST(GeneratedDerivatives, FloatEqualsGeneric) { check_scalar<float>(1e-3); }

TEST(GeneratedDerivatives, AllocateNothing) {
  std::vector<double> q(robot::nq, 0.0), v(robot::nv, 0.5), x(robot::nv), A(robot::nv * robot::nv), B(A), C(A);
  if (MBGEN_FLOATING) q[6] = 1;  // the base's quaternion w
  MallocGuard guard;
#if MBGEN_DERIVATIVES_Q_TAU
  robot::inverse_dynamics_derivatives(q.data(), v.data(), v.data(), x.data(), A.data());
  robot::forward_dynamics_derivatives(q.data(), v.data(), v.data(), x.data(), A.data(), C.data());
#else
  robot::inverse_dynamics_derivatives(q.data(), v.data(), v.data(), x.data(), A.data(), B.data());
  robot::forward_dynamics_derivatives(q.data(), v.data(), v.data(), x.data(), A.data(), B.data(), C.data());
#endif
  EXPECT_EQ(guard.count(), 0u);
  EXPECT_TRUE(std::isfinite(A[0]) && std::isfinite(C[0]));
}

}  // namespace
}  // namespace mbgen::test
