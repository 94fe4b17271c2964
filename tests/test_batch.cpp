// Batch functions (mbgen generate --batch W): every state of <function>_batch equals the one-state
// <function> bit for bit, in double and in float, when both are compiled with the same flags
// (this library: -O2, where g++ contracts and reorders what it may). Compiled once per batch
// robot (tests/CMakeLists.txt) with MBGEN_GENERATED_HEADER and MBGEN_GENERATED_NS defined.
//
// The one-state functions equal the generic runtime (test_generated.cpp), so equality here carries
// that to the batch. The states are valid ones: unit base quaternions, loops closed by the
// generated Newton, M from mass_matrix and its factor from mass_matrix_factor.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include MBGEN_GENERATED_HEADER
#include "test_support.hpp"

namespace gen_ns = MBGEN_GENERATED_NS;

namespace mbgen::test {
namespace {

constexpr int W = gen_ns::batch_width;

template <typename S> using Lane = std::vector<S>;
/// One argument over the batch: its value in each state.
template <typename S> using Argument = std::array<Lane<S>, W>;

/// Structure of arrays: entry i of state w at [i * W + w].
template <typename S> std::vector<S> pack(const Argument<S>& a) {
  std::vector<S> out(a[0].size() * W);
  for (int w = 0; w < W; ++w)
    for (std::size_t i = 0; i < a[0].size(); ++i) out[i * W + static_cast<std::size_t>(w)] = a[static_cast<std::size_t>(w)][i];
  return out;
}
template <typename S> const S (*lanes(const std::vector<S>& x))[W] { return reinterpret_cast<const S(*)[W]>(x.data()); }
template <typename S> S (*lanes(std::vector<S>& x))[W] { return reinterpret_cast<S(*)[W]>(x.data()); }

/// Calls `one` per state and `batch` once, and counts the entries whose bits differ (NaN
/// included: none of these states gives one, and a NaN would count as a difference).
template <typename S, typename OneState, typename Batch>
void expect_bitwise_equal(const std::string& name, const std::vector<Argument<S>>& inputs, const std::vector<int>& output_sizes,
                          OneState one, Batch batch) {
  std::vector<Argument<S>> expected(output_sizes.size());
  for (int w = 0; w < W; ++w) {
    std::vector<const S*> in;
    for (const Argument<S>& a : inputs) in.push_back(a[static_cast<std::size_t>(w)].data());
    std::vector<S*> out;
    for (std::size_t k = 0; k < output_sizes.size(); ++k) {
      expected[k][static_cast<std::size_t>(w)].assign(static_cast<std::size_t>(output_sizes[k]), S(-7));
      out.push_back(expected[k][static_cast<std::size_t>(w)].data());
    }
    one(in.data(), out.data());
  }
  std::vector<std::vector<S>> packed_in, packed_out;
  for (const Argument<S>& a : inputs) packed_in.push_back(pack(a));
  for (int size : output_sizes) packed_out.emplace_back(static_cast<std::size_t>(size) * W, S(-7));
  std::vector<const S (*)[W]> in;
  for (const std::vector<S>& x : packed_in) in.push_back(lanes(x));
  std::vector<S (*)[W]> out;
  for (std::vector<S>& x : packed_out) out.push_back(lanes(x));
  batch(in.data(), out.data());

  int differing = 0, compared = 0;
  std::string first;
  for (std::size_t k = 0; k < output_sizes.size(); ++k)
    for (int w = 0; w < W; ++w)
      for (int i = 0; i < output_sizes[k]; ++i) {
        const S a = expected[k][static_cast<std::size_t>(w)][static_cast<std::size_t>(i)];
        const S b = packed_out[k][static_cast<std::size_t>(i) * W + static_cast<std::size_t>(w)];
        ++compared;
        if (std::memcmp(&a, &b, sizeof(S)) != 0 && differing++ == 0) {
          std::ostringstream s;
          s.precision(17);
          s << "output " << k << " entry " << i << " state " << w << ": " << a << " vs " << b;
          first = s.str();
        }
      }
  EXPECT_EQ(differing, 0) << name << ": " << differing << " of " << compared << " entries differ; first " << first;
  EXPECT_GT(compared, 0) << name;
}

template <typename S> class BatchTest : public ::testing::Test {
 protected:
  /// W valid states: q from the description (a random configuration of a tree; for loops, a
  /// seeded consistent state about the assembled pose, as test_generated.cpp takes them),
  /// rounded to S and closed again by the generated Newton; velocities, forces and accelerations
  /// in [-1, 1].
  void SetUp() override {
    gen::LoadOptions options;
    options.base = MBGEN_FLOATING ? gen::BaseType::Floating : gen::BaseType::Fixed;
    const gen::Description description = gen::load_description(MBGEN_DESCRIPTION, options);
    const Model& model = description.model;
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> unit(-1, 1);
    auto random = [&](int n, double scale) {
      Lane<S> x(static_cast<std::size_t>(n));
      for (S& e : x) e = S(scale * unit(rng));
      return x;
    };
    for (std::size_t w = 0; w < W; ++w) {
      VecX<double> q_double, v_double;
      if (gen_ns::has_loops)
        ASSERT_TRUE(consistent_state(model, description.assembly.q, rng, 0.05, q_double, v_double));
      else
        q_double = random_configuration<double>(model, rng);
      ASSERT_EQ(q_double.size(), gen_ns::nq);
      q[w].assign(q_double.data(), q_double.data() + q_double.size());
      ASSERT_EQ(gen_ns::closure_positions(q[w].data()).status, gen_ns::ClosureStatus::converged);
      v[w] = random(gen_ns::nv, 1.0);
      vy[w] = random(gen_ns::ny, 1.0);
      a[w] = random(gen_ns::nv, 1.0);
      ydd[w] = random(gen_ns::ny, 1.0);
      tau[w] = random(gen_ns::nv, 1.0);
      M[w].resize(gen_ns::nv * gen_ns::nv);
      gen_ns::mass_matrix(q[w].data(), M[w].data());
      LD[w].resize(M[w].size());
      gen_ns::mass_matrix_factor(M[w].data(), LD[w].data());
    }
  }
  Argument<S> q, v, vy, a, ydd, tau, M, LD;
};

using Scalars = ::testing::Types<double, float>;
TYPED_TEST_SUITE(BatchTest, Scalars);

// One case per batched function: the one-state call and the batch call on the same arguments.
#define MBGEN_BATCH_CASE(function, inputs, outputs, ...)                                                   \
  expect_bitwise_equal<S>(#function, inputs, outputs, [](const S* const* i, S* const* o) { gen_ns::function(__VA_ARGS__); }, \
                          [](const S(*const* i)[W], S(*const* o)[W]) { gen_ns::function##_batch(__VA_ARGS__); })

TYPED_TEST(BatchTest, DynamicsEqualTheOneStateFunctionsBitForBit) {
  using S = TypeParam;
  constexpr int nv = gen_ns::nv, ny = gen_ns::ny;
  MBGEN_BATCH_CASE(forward_dynamics, (std::vector<Argument<S>>{this->q, this->vy, this->tau}), (std::vector<int>{ny}), i[0], i[1],
                   i[2], o[0]);
  MBGEN_BATCH_CASE(inverse_dynamics, (std::vector<Argument<S>>{this->q, this->v, this->a}), (std::vector<int>{nv}), i[0], i[1],
                   i[2], o[0]);
  MBGEN_BATCH_CASE(actuator_forces, (std::vector<Argument<S>>{this->q, this->vy, this->ydd}),
                   (std::vector<int>{gen_ns::na, ny}), i[0], i[1], i[2], o[0], o[1]);
}

TYPED_TEST(BatchTest, MassMatrixAndItsFactorEqualTheOneStateFunctionsBitForBit) {
  using S = TypeParam;
  constexpr int nv = gen_ns::nv;
  MBGEN_BATCH_CASE(mass_matrix, (std::vector<Argument<S>>{this->q}), (std::vector<int>{nv * nv}), i[0], o[0]);
  MBGEN_BATCH_CASE(mass_matrix_factor, (std::vector<Argument<S>>{this->M}), (std::vector<int>{nv * nv}), i[0], o[0]);
  MBGEN_BATCH_CASE(mass_matrix_solve, (std::vector<Argument<S>>{this->LD, this->tau}), (std::vector<int>{nv}), i[0], i[1], o[0]);
}

TYPED_TEST(BatchTest, KinematicsEqualTheOneStateFunctionsBitForBit) {
  using S = TypeParam;
  constexpr int nv = gen_ns::nv;
  const std::vector<Argument<S>> q{this->q};
  MBGEN_BATCH_CASE(forward_kinematics, q, (std::vector<int>{gen_ns::num_bodies * 12}), i[0], o[0]);
  MBGEN_BATCH_CASE(frame_poses, q, (std::vector<int>{gen_ns::num_frames * 12}), i[0], o[0]);
  MBGEN_BATCH_CASE(frame_jacobians, q, (std::vector<int>{gen_ns::num_frames * 6 * nv}), i[0], o[0]);
  MBGEN_BATCH_CASE(center_of_mass, q, (std::vector<int>{3}), i[0], o[0]);
  MBGEN_BATCH_CASE(centroidal_momentum_matrix, q, (std::vector<int>{6 * nv}), i[0], o[0]);
}

// The derivatives (generated with fd_derivatives and id_derivatives: MBGEN_BATCH_DERIVATIVES): the
// trace on the lanes, then the factor's solves on the lanes (emit_derivatives.cpp).
#if MBGEN_BATCH_DERIVATIVES
TYPED_TEST(BatchTest, DerivativesEqualTheOneStateFunctionsBitForBit) {
  using S = TypeParam;
  constexpr int nv = gen_ns::nv, ny = gen_ns::ny;
  MBGEN_BATCH_CASE(inverse_dynamics_derivatives, (std::vector<Argument<S>>{this->q, this->v, this->a}),
                   (std::vector<int>{nv, nv * nv, nv * nv}), i[0], i[1], i[2], o[0], o[1], o[2]);
  // A tree's: qdd, dqdd/dq, dqdd/dv, M^-1; a closed system's: in its ny independent coordinates,
  // dydd/dtau ny x nv.
  MBGEN_BATCH_CASE(forward_dynamics_derivatives, (std::vector<Argument<S>>{this->q, this->vy, this->tau}),
                   (std::vector<int>{ny, ny * ny, ny * ny, ny * nv}), i[0], i[1], i[2], o[0], o[1], o[2], o[3]);
}
#endif

}  // namespace
}  // namespace mbgen::test
