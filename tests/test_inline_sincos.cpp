// The inline sin and cos of code generated with --batch (sincos.fmt, sincos_of): within one ulp of
// 1 of the true values (long double reference) over the range they promise, |x| < 2^20 pi/2 in
// double and 2^16 pi/2 in float; NaN beyond it and for NaN or infinite angles; the batch's lanes
// equal the one-state values bit for bit, out of range too. Read through tiny_arm's generated
// forward kinematics: its shoulder turns about y from the base, so body 0's rotation is
// [cos q 0 sin q; 0 1 0; -sin q 0 cos q] and X_WB[0] and X_WB[2] are cos q0 and sin q0 as computed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <type_traits>

#include "tiny_arm_batch.hpp"

namespace {

namespace arm = tiny_arm_batch;
constexpr int W = arm::batch_width;

template <typename S> struct SinCosValue {
  S sin, cos;
};
template <typename S> SinCosValue<S> one_state(S angle) {
  S q[arm::nq] = {angle, S(0), S(0)}, X[arm::num_bodies * 12];
  arm::forward_kinematics(q, X);
  return {X[2], X[0]};
}

template <typename S> class InlineSinCos : public ::testing::Test {};
using Scalars = ::testing::Types<double, float>;
TYPED_TEST_SUITE(InlineSinCos, Scalars);

TYPED_TEST(InlineSinCos, WithinAnUlpOfOneOverItsRange) {
  using S = TypeParam;
  const long double limit = std::is_same_v<S, double> ? 0x1p20L * 1.5707963267948966L : 0x1p16L * 1.5707963267948966L;
  const long double ulp_of_one = std::numeric_limits<S>::epsilon();
  std::mt19937_64 rng(11);
  long double worst = 0;
  for (const long double range : {1.0L, 10.0L, 1e3L, 0.999L * limit}) {
    std::uniform_real_distribution<long double> angle(-range, range);
    for (int trial = 0; trial < 20000; ++trial) {
      const S x = static_cast<S>(angle(rng));
      const SinCosValue<S> v = one_state(x);
      worst = std::max({worst, std::fabs(v.sin - std::sin(static_cast<long double>(x))),
                        std::fabs(v.cos - std::cos(static_cast<long double>(x)))});
    }
  }
  // Near the zeros the error is relative to the value: sin of a tiny angle is the angle.
  for (const S tiny : {S(1e-30), S(-3e-20), S(1e-8)}) EXPECT_EQ(one_state(tiny).sin, tiny);
  EXPECT_EQ(one_state(S(0)).cos, S(1));
  EXPECT_LE(worst, ulp_of_one) << "worst error " << static_cast<double>(worst / ulp_of_one) << " ulp of 1";
  this->RecordProperty("worst_ulp_of_one", std::to_string(static_cast<double>(worst / ulp_of_one)));
}

TYPED_TEST(InlineSinCos, NaNBeyondTheRangeAndForNaNOrInfiniteAngles) {
  using S = TypeParam;
  const S beyond = std::is_same_v<S, double> ? S(0x1p20 * 1.5708) : S(0x1p16 * 1.5708);
  for (const S x : {beyond, -beyond, S(1e30), std::numeric_limits<S>::infinity(), -std::numeric_limits<S>::infinity(),
                    std::numeric_limits<S>::quiet_NaN()}) {
    const SinCosValue<S> v = one_state(x);
    EXPECT_TRUE(std::isnan(v.sin) && std::isnan(v.cos)) << x << ": " << v.sin << ", " << v.cos;
  }
}

TYPED_TEST(InlineSinCos, LanesEqualOneStateBitForBit) {
  using S = TypeParam;
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> angle(-2e5, 2e5);  // in range for double, partly beyond for float
  int differing = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    S q[arm::nq][W] = {}, X[arm::num_bodies * 12][W];
    for (int w = 0; w < W; ++w) q[0][w] = static_cast<S>(trial % 7 == 0 ? angle(rng) : angle(rng) * 1e-5);
    arm::forward_kinematics_batch(q, X);
    for (int w = 0; w < W; ++w) {
      const SinCosValue<S> v = one_state(q[0][w]);
      differing += std::memcmp(&v.sin, &X[2][w], sizeof(S)) != 0 || std::memcmp(&v.cos, &X[0][w], sizeof(S)) != 0;
    }
  }
  EXPECT_EQ(differing, 0);
}

}  // namespace
