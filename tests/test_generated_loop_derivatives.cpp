// A closed system's generated NAME::forward_dynamics_derivatives (fd_derivatives with loops:
// the independent coordinates' accelerations and their derivatives) against the generic
// runtime's forward_dynamics_loops_derivatives, which test_loop_dynamics_derivatives.cpp checks
// against dual numbers and central differences: double to 1e-12, float to 1e-4 relative
// (max-norm over the generic result's max-norm, weighted by M_y as there: a solve with an
// ill-conditioned M_y; float through the closure's Givens factor and two solves), at consistent
// states drawn around the assembled pose; no allocation. Compiled once per robot with
// MBGEN_GENERATED_HEADER, MBGEN_GENERATED_NS, MBGEN_DESCRIPTION, MBGEN_EXTRAS and MBGEN_FLOATING
// (tests/CMakeLists.txt: mbgen_add_generated_loop_derivatives_test).
#include <gtest/gtest.h>

#include <random>

#include MBGEN_GENERATED_HEADER
#include "derivative_errors.hpp"
#include "malloc_guard.hpp"
#include "mbgen/algorithm/loop_dynamics_derivatives.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

namespace robot = MBGEN_GENERATED_NS;

gen::Description load() {
  gen::LoadOptions options;
  options.base = MBGEN_FLOATING ? gen::BaseType::Floating : gen::BaseType::Fixed;
  if (std::string(MBGEN_EXTRAS).size() > 0) options.extras_file = MBGEN_EXTRAS;
  return gen::load_description(MBGEN_DESCRIPTION, options);
}

/// A row-major rows x cols output as a matrix.
template <typename T> void check_scalar(double tolerance) {
  const gen::Description d = load();
  const Model& model = d.model;
  ASSERT_FALSE(model.subsystems.empty());
  ASSERT_EQ(model.nq(), robot::nq);
  ASSERT_EQ(model.nv(), robot::nv);
  const int ny = model.structure().num_independent(), nv = model.nv();
  ASSERT_EQ(ny, robot::ny);
  Data<double> data(model);
  LoopDynamicsDerivatives<double> ld(model);
  std::mt19937_64 rng(546);
  int states = 0;
  double worst = 0;
  for (int trial = 0; trial < 20 && states < 4; ++trial) {
    VecX<double> q, v;
    if (!consistent_state(model, d.assembly.q, rng, 0.05, q, v)) continue;
    ++states;
    VecX<double> yd(ny);
    for (int i = 0; i < ny; ++i) yd[i] = v[model.structure().independent_v[static_cast<std::size_t>(i)]];
    const VecX<double> tau = random_vector<double>(nv, rng, 5.0);
    ASSERT_EQ(forward_dynamics_loops_derivatives<double>(model, data, ld, q, yd, tau), ClosureStatus::Converged);
    const std::vector<T> qt = as<T>(q), ydt = as<T>(yd), taut = as<T>(tau);
    std::vector<T> ydd(static_cast<std::size_t>(ny)), A(static_cast<std::size_t>(ny * ny)), B(A), C(static_cast<std::size_t>(ny * nv));
    robot::forward_dynamics_derivatives(qt.data(), ydt.data(), taut.data(), ydd.data(), A.data(), B.data(), C.data());
    worst = std::max(worst, weighted_relative(ld.M_y, matrix(ydd, ny, 1), ld.ydd));
    worst = std::max(worst, weighted_relative(ld.M_y, matrix(A, ny, ny), ld.dydd_dy));
    worst = std::max(worst, weighted_relative(ld.M_y, matrix(B, ny, ny), ld.dydd_dyd));
    worst = std::max(worst, weighted_relative(ld.M_y, matrix(C, ny, nv), ld.dydd_dtau));
  }
  std::printf("  generated against generic (%s): %.1e over %d states\n", sizeof(T) == 8 ? "double" : "float", worst, states);
  EXPECT_EQ(states, 4);
  EXPECT_LT(worst, tolerance);
}

TEST(GeneratedLoopDerivatives, DoubleEqualsGeneric) { check_scalar<double>(1e-12); }
TEST(GeneratedLoopDerivatives, FloatEqualsGeneric) { check_scalar<float>(1e-4); }

TEST(GeneratedLoopDerivatives, AllocateNothing) {
  const gen::Description d = load();
  std::vector<double> q(d.assembly.q.data(), d.assembly.q.data() + robot::nq), v(robot::ny, 0.5), tau(robot::nv, 1.0), ydd(robot::ny),
      A(robot::ny * robot::ny), B(A), C(robot::ny * robot::nv);
  MallocGuard guard;
  robot::forward_dynamics_derivatives(q.data(), v.data(), tau.data(), ydd.data(), A.data(), B.data(), C.data());
  EXPECT_EQ(guard.count(), 0u);
  EXPECT_TRUE(std::isfinite(A[0]) && std::isfinite(C[0]));
}

}  // namespace
}  // namespace mbgen::test
