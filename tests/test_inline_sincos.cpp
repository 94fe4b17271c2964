// The inline sin and cos of generated code (sincos.fmt). Every one-state function takes the sines
// and cosines of its angles at once (sincos_all: sincos_of in a loop): within one ulp of 1 of the
// true values (long double reference) over sincos_of's range, |x| < 2^20 pi/2 in double and
// 2^16 pi/2 in float, and libm's own values beyond it. A batch's lanes (sincos_of on vectors)
// equal the one-state values bit for bit within the range, and are NaN beyond it and for NaN or
// infinite angles. Compiled with -ffast-math, which would fold sincos_of's rounding away, the
// one-state functions call libm. Read through tiny_arm's generated forward kinematics: its
// shoulder turns about y from the base, so body 0's rotation is
// [cos q 0 sin q; 0 1 0; -sin q 0 cos q] and X_WB[0] and X_WB[2] are cos q0 and sin q0 as computed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <type_traits>

#include "tiny_arm_batch.hpp"
#include "tiny_arm_fast_math.hpp"

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
template <typename S> SinCosValue<S> fast_math(S angle) {
  S q[tiny_arm_fast_math::nq] = {angle, S(0), S(0)}, X[tiny_arm_fast_math::num_bodies * 12];
  tiny_arm_fast_math::forward_kinematics(q, X);
  return {X[2], X[0]};
}
template <typename S> S beyond_the_range() { return std::is_same_v<S, double> ? S(0x1p20 * 1.5708) : S(0x1p16 * 1.5708); }
template <typename S> bool same_bits(S a, S b) { return std::memcmp(&a, &b, sizeof(S)) == 0; }

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

TYPED_TEST(InlineSinCos, BeyondTheRangeOneStateIsLibmAndLanesAreNaN) {
  using S = TypeParam;
  const S beyond = beyond_the_range<S>();
  for (const S x : {beyond, -beyond, S(1e30), std::numeric_limits<S>::infinity(), -std::numeric_limits<S>::infinity(),
                    std::numeric_limits<S>::quiet_NaN()}) {
    const SinCosValue<S> v = one_state(x);
    if (std::isfinite(x)) {
      EXPECT_TRUE(same_bits(v.sin, std::sin(x)) && same_bits(v.cos, std::cos(x))) << x << ": " << v.sin << ", " << v.cos;
    } else {
      EXPECT_TRUE(std::isnan(v.sin) && std::isnan(v.cos)) << x << ": " << v.sin << ", " << v.cos;
    }
    S q[arm::nq][W] = {}, X[arm::num_bodies * 12][W];
    for (int w = 0; w < W; ++w) q[0][w] = x;
    arm::forward_kinematics_batch(q, X);
    for (int w = 0; w < W; ++w) EXPECT_TRUE(std::isnan(X[2][w]) && std::isnan(X[0][w])) << x << " lane " << w;
  }
}

TYPED_TEST(InlineSinCos, LanesEqualOneStateBitForBit) {
  using S = TypeParam;
  std::mt19937_64 rng(12);
  // Up to half the range, and small angles.
  const double range = static_cast<double>(beyond_the_range<S>()) / 2;
  std::uniform_real_distribution<double> angle(-range, range);
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

// Without the -ffast-math branch sincos_of would run with its rounding folded away (k = x 2/pi,
// not an integer) and give no sine at all; with it, libm's values (within 4 ulp of 1, the
// vector libm -ffast-math may call included).
TYPED_TEST(InlineSinCos, FastMathBuildsCallLibm) {
  using S = TypeParam;
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> angle(-10.0, 10.0);
  long double worst = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    const S x = static_cast<S>(trial % 100 == 0 ? angle(rng) * 1e6 : angle(rng));
    const SinCosValue<S> v = fast_math(x);
    worst = std::max({worst, std::fabs(v.sin - std::sin(static_cast<long double>(x))),
                      std::fabs(v.cos - std::cos(static_cast<long double>(x)))});
  }
  EXPECT_LE(worst, 4 * std::numeric_limits<S>::epsilon()) << "worst error " << static_cast<double>(worst) << " (fast-math build)";
}

}  // namespace
