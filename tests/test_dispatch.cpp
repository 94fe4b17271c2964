// The AVX2 copies g++ makes of the generated statements at the default flags on x86-64 Linux
// (templates/cpp/noinline_macro.fmt) give the baseline copy's results bit for bit: AVX2 without
// FMA contracts no multiply-add, and g++ reassociates nothing, so vectorising a statement changes
// where its operations run, not how they round. hyq_dispatched and hyq_one_copy are the same
// generation, the second compiled with MBGEN_NO_DISPATCH (tests/CMakeLists.txt; ctest dispatch.*
// checks the copies are there, and absent from the second).
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "hyq_dispatched.hpp"
#include "hyq_one_copy.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

template <typename S>
int differing_bits(const S* a, const S* b, int n) {
  int differing = 0;
  for (int i = 0; i < n; ++i) differing += std::memcmp(&a[i], &b[i], sizeof(S)) != 0;
  return differing;
}

template <typename S>
void expect_same_bits() {
  constexpr int nq = hyq_dispatched::nq, nv = hyq_dispatched::nv;
  static_assert(nq == hyq_one_copy::nq && nv == hyq_one_copy::nv);
  const Model model = load_tree(MBGEN_SHARED_ROBOTS "/hyq/hyq_no_sensors.urdf", gen::BaseType::Floating);
  ASSERT_EQ(model.nq(), nq);
  std::mt19937_64 rng(11);
  int differing = 0, compared = 0, nonzero = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const VecX<S> q = random_configuration<double>(model, rng).template cast<S>();
    const VecX<S> v = random_vector<double>(nv, rng, 3.0).template cast<S>();
    const VecX<S> u = random_vector<double>(nv, rng, 20.0).template cast<S>();
    S a[nv], b[nv], Ma[nv * nv], Mb[nv * nv];
    hyq_dispatched::inverse_dynamics(q.data(), v.data(), u.data(), a);
    hyq_one_copy::inverse_dynamics(q.data(), v.data(), u.data(), b);
    differing += differing_bits(a, b, nv);
    for (int i = 0; i < nv; ++i) nonzero += a[i] != 0;
    hyq_dispatched::forward_dynamics(q.data(), v.data(), u.data(), a);
    hyq_one_copy::forward_dynamics(q.data(), v.data(), u.data(), b);
    differing += differing_bits(a, b, nv);
    for (int i = 0; i < nv; ++i) nonzero += a[i] != 0;
    hyq_dispatched::mass_matrix(q.data(), Ma);
    hyq_one_copy::mass_matrix(q.data(), Mb);
    differing += differing_bits(Ma, Mb, nv * nv);
    compared += 2 * nv + nv * nv;
  }
  EXPECT_EQ(differing, 0) << "of " << compared << " outputs";
  EXPECT_GT(nonzero, 2 * 200 * nv * 9 / 10);  // the comparison is of computed values, not of zeros
}

TEST(Dispatch, AvxCopiesEqualTheBaselineBitForBit) {
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "this CPU has no AVX2: both libraries run their baseline copy";
  expect_same_bits<double>();
  expect_same_bits<float>();
}

}  // namespace
}  // namespace mbgen::test
