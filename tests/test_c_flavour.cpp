// The c flavour (templates/c, `mbgen generate --flavour c`) equals the cpp flavour bit for bit:
// c_flavour_probe.c, a C99 file, calls every function of the robot's C API; this test makes the
// same calls on the cpp flavour's API and compares every value's bits, for double and float.
// Both flavours frame the same statements (codegen's C++ is shared), so any difference is a
// template bug: a wrong argument order, a scalar mix-up, a conversion in the closure options.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <type_traits>
#include <vector>

#include MBGEN_CPP_HEADER

namespace ns = MBGEN_NS;

extern "C" {
int c_probe_size(void);
int c_probe_double(const double* q0, const double* vy, const double* tau, double* out);
int c_probe_float(const float* q0, const float* vy, const float* tau, float* out);
}

namespace {

/// The cpp flavour's results in c_flavour_probe.c's order.
template <typename S> std::vector<S> cpp_results(const S* q0, const S* vy, const S* tau) {
  constexpr int np = ns::num_distance_pairs;
  S q[ns::nq], qdd_y[ns::ny], qdd[ns::nv], T[ns::nv * ns::ny], v[ns::nv], g[ns::nv], vy2[ns::ny];
  S tau_out[ns::nv], M[ns::nv * ns::nv], X[12 * ns::num_bodies], XF[12 * ns::num_frames];
  S JF[6 * ns::num_frames * ns::nv], com[3], Ag[6 * ns::nv];
  std::vector<S> d(np), n(3 * np), w(6 * np), Jd(np * ns::nv);
  std::copy(q0, q0 + ns::nq, q);
  const auto r = ns::closure_positions(q);
  ns::forward_dynamics(q, vy, tau, qdd_y);
  ns::full_accelerations(q, vy, tau, qdd);
  ns::velocity_map(q, T);
  ns::full_velocities(q, vy, v);
  ns::acceleration_bias(q, vy, g);
  ns::independent_velocities(v, vy2);
  ns::inverse_dynamics(q, v, qdd, tau_out);
  ns::mass_matrix(q, M);
  ns::forward_kinematics(q, X);
  ns::frame_poses(q, XF);
  ns::frame_jacobians(q, JF);
  ns::center_of_mass(q, com);
  ns::centroidal_momentum_matrix(q, Ag);
  ns::self_distances(q, d.data(), n.data(), w.data(), Jd.data());
  std::vector<S> out(q, q + ns::nq);
  for (S x : {S(static_cast<int>(r.status)), S(r.iterations), r.residual, r.pivot_ratio, r.relative_pivot_ratio})
    out.push_back(x);
  auto put = [&](const S* a, std::size_t size) { out.insert(out.end(), a, a + size); };
  put(qdd_y, ns::ny);
  put(qdd, ns::nv);
  put(T, ns::nv * ns::ny);
  put(v, ns::nv);
  put(g, ns::nv);
  put(vy2, ns::ny);
  put(tau_out, ns::nv);
  put(M, ns::nv * ns::nv);
  put(X, 12 * ns::num_bodies);
  put(XF, 12 * ns::num_frames);
  put(JF, 6 * ns::num_frames * ns::nv);
  put(com, 3);
  put(Ag, 6 * ns::nv);
  for (const auto* a : {&d, &n, &w, &Jd}) put(a->data(), a->size());
  S q2[ns::nq], v2[ns::nv];
  std::copy(q0, q0 + ns::nq, q2);
  std::fill(v2, v2 + ns::nv, S(1));
  for (int i = 0; i < ns::ny; ++i) v2[ns::independent_v_index[i]] = vy[i];
  const auto r2 = ns::close_loops(q2, v2);
  put(q2, ns::nq);
  out.push_back(S(r2.iterations));
  put(v2, ns::nv);
  return out;
}

template <typename S> void expect_bitwise_equal(int seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> small(-0.1, 0.1), unit(-1, 1);
  S q[ns::nq], vy[ns::ny], tau[ns::nv];
  // Small independent coordinates, the dependent ones' warm start at 0 (near the assembled pose):
  // a state the closure reaches. (Without loops every coordinate is independent.)
  for (S& x : q) x = ns::has_loops ? S(0) : S(small(rng));
  if (ns::has_loops) {
    static_assert(ns::nq == ns::nv || !ns::has_loops, "a fixed base: q and v indices agree");
    for (int i : ns::independent_v_index) q[i] = S(0.2 * small(rng));  // within 2 cm: the ankle's drives are slides
  }
  if (ns::floating_base) {  // a unit quaternion, scalar last
    double quat[4], norm = 0;
    for (double& c : quat) {
      c = unit(rng);
      norm += c * c;
    }
    for (int i = 0; i < 4; ++i) q[3 + i] = S(quat[i] / std::sqrt(norm));
  }
  for (S& x : vy) x = S(unit(rng));
  for (S& x : tau) x = S(unit(rng));
  const std::vector<S> expected = cpp_results(q, vy, tau);
  std::vector<S> from_c(static_cast<std::size_t>(c_probe_size()));
  int written = 0;
  if constexpr (std::is_same_v<S, double>)
    written = c_probe_double(q, vy, tau, from_c.data());
  else
    written = c_probe_float(q, vy, tau, from_c.data());
  ASSERT_EQ(written, static_cast<int>(expected.size()));
  ASSERT_EQ(from_c.size(), expected.size());
  EXPECT_EQ(expected[ns::nq], S(0)) << "closure status: the state must be one the closure reaches";
  int differing = 0;
  for (std::size_t i = 0; i < expected.size(); ++i)
    if (std::memcmp(&expected[i], &from_c[i], sizeof(S)) != 0 && ++differing <= 5)
      ADD_FAILURE() << "value " << i << ": cpp flavour " << expected[i] << ", c flavour " << from_c[i];
  EXPECT_EQ(differing, 0) << "of " << expected.size() << " values";
}

}  // namespace

TEST(CFlavour, EqualsTheCppFlavourBitForBitInDouble) {
  for (int seed = 0; seed < 5; ++seed) expect_bitwise_equal<double>(seed);
}

TEST(CFlavour, EqualsTheCppFlavourBitForBitInFloat) {
  for (int seed = 0; seed < 5; ++seed) expect_bitwise_equal<float>(seed);
}
