// mbgen_add_robot(... ARCH x86-64-v3): the generated forward dynamics compiled for AVX2 and FMA
// (contracted multiply-adds round once instead of twice) still equals the generic ABA to 1e-12,
// on a CPU that can run it. That the flags reach the compiler is checked on the object code
// (ctest arch.*: FMA instructions in this library, none in the same code at the build's flags).
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "iiwa14_v3.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

TEST(Arch, X86_64_V3ForwardDynamicsEqualsGeneric) {
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma") || !__builtin_cpu_supports("bmi2"))
    GTEST_SKIP() << "this CPU cannot run x86-64-v3 code";
  const Model model = load_tree(MBGEN_SHARED_ROBOTS "/iiwa14/iiwa14_primitive_collision.urdf", gen::BaseType::Fixed);
  ASSERT_EQ(model.nv(), iiwa14_v3::nv);
  Data<double> data(model);
  std::mt19937_64 rng(3);
  double worst = 0;
  VecX<double> qdd(model.nv());
  for (int trial = 0; trial < 100; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    const VecX<double> v = random_vector<double>(model.nv(), rng, 2.0);
    const VecX<double> tau = random_vector<double>(model.nv(), rng, 10.0);
    iiwa14_v3::forward_dynamics(q.data(), v.data(), tau.data(), qdd.data());
    const VecX<double> expected = aba<double>(model, data, q, v, tau);
    worst = std::max(worst, relative_error(qdd, expected));
  }
  EXPECT_LT(worst, 1e-12);
}

// The batch under the same flags: g++ contracts the vector statements as it contracts the scalar
// ones (one basic block each: batch_source.fmt unrolls its loops over the lanes), so every state
// equals the one-state function bit for bit, FMA and all.
TEST(Arch, X86_64_V3BatchEqualsTheOneStateFunctionBitForBit) {
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma") || !__builtin_cpu_supports("bmi2"))
    GTEST_SKIP() << "this CPU cannot run x86-64-v3 code";
  constexpr int W = iiwa14_v3::batch_width, nv = iiwa14_v3::nv;
  const Model model = load_tree(MBGEN_SHARED_ROBOTS "/iiwa14/iiwa14_primitive_collision.urdf", gen::BaseType::Fixed);
  std::mt19937_64 rng(5);
  int differing = 0;
  for (int trial = 0; trial < 25; ++trial) {
    double q[nv][W], v[nv][W], tau[nv][W], qdd[nv][W], one[W][nv];
    for (int w = 0; w < W; ++w) {
      const VecX<double> qw = random_configuration<double>(model, rng);
      const VecX<double> vw = random_vector<double>(nv, rng, 2.0), tw = random_vector<double>(nv, rng, 10.0);
      for (int i = 0; i < nv; ++i) q[i][w] = qw[i], v[i][w] = vw[i], tau[i][w] = tw[i];
      iiwa14_v3::forward_dynamics(qw.data(), vw.data(), tw.data(), one[w]);
    }
    iiwa14_v3::forward_dynamics_batch(q, v, tau, qdd);
    for (int w = 0; w < W; ++w)
      for (int i = 0; i < nv; ++i) differing += std::memcmp(&qdd[i][w], &one[w][i], sizeof(double)) != 0;
  }
  EXPECT_EQ(differing, 0) << "of " << 25 * W * nv << " accelerations";
}

}  // namespace
}  // namespace mbgen::test
