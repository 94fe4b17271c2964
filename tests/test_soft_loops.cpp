// The soft loops of a continuation span (runtime/include/mbgen/sim/soft_loops.hpp): the ground's
// joint forces through the backend's contact_points against the runtime's own joint-space
// mapping (contact_joint_forces, body chains and world-axes columns: a different path), and the
// soft dynamics in full coordinates against the exact O(n) recursion with sub-systems when the
// rows are made hard (impedance -> 1) at consistent states, on Lola (four loops, floating base)
// and the slider-crank; and what the softness does: the rows' acceleration misses the reference
// by exactly the regularisation, (1 - d) / d diag(A) lambda.
#include <gtest/gtest.h>

#include <random>

#include "collision/contact_spheres.hpp"
#include "mbgen/sim/backend.hpp"
#include "mbgen/sim/soft_loops.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

using sim::GenericBackend;

gen::Description load(const std::string& urdf, const std::string& extras, gen::BaseType base) {
  gen::LoadOptions options;
  options.extras_file = extras;
  options.base = base;
  return gen::load_description(urdf, options);
}

gen::Description lola() {
  return load(MBGEN_SOURCE_DIR "/robots/lola/lola.urdf", MBGEN_SOURCE_DIR "/robots/lola/lola.yaml", gen::BaseType::Floating);
}

TEST(SoftLoops, GroundJointForcesEqualTheRuntimesJointSpaceMapping) {
  const gen::Description d = lola();
  const std::vector<ContactSphere> spheres = gen::contact_spheres(d);
  ASSERT_FALSE(spheres.empty());
  GenericBackend<double> backend(d.model, spheres);
  const int nv = d.model.nv(), nc = static_cast<int>(spheres.size());
  const GroundPlane ground = GroundPlane::tilted_about_x(0.05);
  const ContactParameters parameters;
  double g[kGroundInputs], l[kLawInputs];
  contact_inputs(ground, parameters, g, l);
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> unit(-1, 1);
  Data<double> reference(d.model);
  for (int trial = 0; trial < 3; ++trial) {
    const VecX<double> q = sunk_into_ground(d, spheres, 1e-3);
    VecX<double> v(nv), tau(nv);
    for (int i = 0; i < nv; ++i) v[i] = 0.3 * unit(rng), tau[i] = 20 * unit(rng);
    VecX<double> expected = tau, out(kContactOutputs * nc);
    contact_joint_forces<double>(d.model, reference, spheres, parameters.exponent, q, v.data(), g, l, expected.data(), out.data());
    VecX<double> got = tau, points(3 * nc), jacobians(6 * nv * nc);
    std::vector<sim::ContactReport<double>> reports(static_cast<std::size_t>(nc));
    sim::add_ground_joint_forces<GenericBackend<double>, double>(backend, ground, parameters, q.data(), v.data(), points.data(),
                                                                 jacobians.data(), got.data(), reports.data());
    EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-10 * (expected - tau).cwiseAbs().maxCoeff()) << trial;
    EXPECT_GT((expected - tau).cwiseAbs().maxCoeff(), 10.0) << "the ground did act";
    int pressing = 0;
    for (int k = 0; k < nc; ++k) {
      const sim::ContactReport<double>& r = reports[static_cast<std::size_t>(k)];
      EXPECT_NEAR(r.penetration, out[kContactOutputs * k], 1e-15) << k;
      if (!r.active) continue;
      ++pressing;
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(r.force[i], out[kContactOutputs * k + 4 + i], 1e-9 * r.force.norm()) << k;
    }
    EXPECT_GT(pressing, 0);
    EXPECT_LT(pressing, nc);
  }
}

// Copied and moved before its first solve (the simulator moves one into place): Eigen's sized LLT
// leaves its status unset until a first factorisation, which the copy would read (a sanitizer
// report, docs/reliability.md); every copy computes what the original does, bit for bit.
TEST(SoftLoops, CopiedAndMovedBeforeFirstUse) {
  const gen::Description d =
      load(MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.urdf", MBGEN_TEST_DATA "/mechanisms/slider_crank_slider_driven.yaml",
           gen::BaseType::Fixed);
  GenericBackend<double> backend(d.model);
  const int nv = d.model.nv();
  sim::SoftLoops<double> fresh(nv, backend.num_closure_rows());
  sim::SoftLoops<double> copied(fresh), assigned;
  assigned = fresh;
  sim::SoftLoops<double> moved(std::move(fresh));
  const sim::ContinuationOptions o;
  const VecX<double> v = VecX<double>::Constant(nv, 0.5), tau = VecX<double>::Constant(nv, 2.0);
  VecX<double> a(nv), b(nv), c(nv);
  ASSERT_TRUE(copied.accelerations(backend, o, 1e-3, d.assembly.q.data(), v.data(), tau.data(), a.data()));
  ASSERT_TRUE(assigned.accelerations(backend, o, 1e-3, d.assembly.q.data(), v.data(), tau.data(), b.data()));
  ASSERT_TRUE(moved.accelerations(backend, o, 1e-3, d.assembly.q.data(), v.data(), tau.data(), c.data()));
  EXPECT_EQ(a, b);
  EXPECT_EQ(a, c);
  EXPECT_TRUE(a.allFinite());
}

/// At consistent states, the soft rows with d = 1 - 1e-12 are the hard constraint: the full
/// accelerations of the O(n) recursion with sub-systems, to 1e-8 of their size.
void expect_hard_limit(const gen::Description& d, int seed) {
  GenericBackend<double> backend(d.model);
  const int nv = d.model.nv();
  sim::SoftLoops<double> soft(nv, backend.num_closure_rows());
  sim::ContinuationOptions o;
  o.impedance = 1 - 1e-12;
  std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
  Data<double> data(d.model);
  for (int trial = 0; trial < 3; ++trial) {
    VecX<double> q, v;
    ASSERT_TRUE(consistent_state(d.model, d.assembly.q, rng, 0.05, q, v));
    const VecX<double> tau = random_vector<double>(nv, rng, 10.0);
    VecX<double> qdd(nv), exact(nv);
    ASSERT_TRUE(soft.accelerations(backend, o, 1e-3, q.data(), v.data(), tau.data(), qdd.data()));
    backend.accelerations(q.data(), v.data(), tau.data(), exact.data());
    EXPECT_LT((qdd - exact).cwiseAbs().maxCoeff(), 1e-8 * std::max(1.0, exact.cwiseAbs().maxCoeff())) << trial;
  }
}

TEST(SoftLoops, HardLimitIsTheExactDynamicsOnLola) { expect_hard_limit(lola(), 22); }

TEST(SoftLoops, HardLimitIsTheExactDynamicsOnTheSliderCrank) {
  expect_hard_limit(load(MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.urdf", MBGEN_TEST_DATA "/mechanisms/slider_crank_slider_driven.yaml",
                         gen::BaseType::Fixed),
                    23);
}

// Soft rows (d = 0.9) at an open pose: the multipliers solve (A + R) lambda = a_ref - J a0, so the
// rows' acceleration J qdd misses a_ref = gamma - b J v - k Phi by exactly -R lambda, and the
// equations of motion hold with the constraint forces J^T lambda.
TEST(SoftLoops, SoftRowsMissTheReferenceByTheRegularisation) {
  const gen::Description d = lola();
  GenericBackend<double> backend(d.model);
  const int nv = d.model.nv(), rows = backend.num_closure_rows();
  sim::SoftLoops<double> soft(nv, rows);
  sim::ContinuationOptions o;
  o.impedance = 0.9;
  o.time_constant = 0.02;
  std::mt19937_64 rng(24);
  VecX<double> q, v;
  ASSERT_TRUE(consistent_state(d.model, d.assembly.q, rng, 0.05, q, v));
  for (const SubSystem& s : d.model.subsystems)  // open the loops by 1e-3 and give the rows a velocity
    for (int z : s.dependent) q[d.model.q_index_of_v(z)] += 1e-3, v[z] += 0.1;
  const VecX<double> tau = random_vector<double>(nv, rng, 10.0);
  VecX<double> qdd(nv);
  ASSERT_TRUE(soft.accelerations(backend, o, 1e-3, q.data(), v.data(), tau.data(), qdd.data()));
  VecX<double> Phi(rows), gamma(rows), Jbuf(rows * nv), M(nv * nv), bias(nv);
  backend.closure_constraints(q.data(), v.data(), Phi.data(), Jbuf.data(), gamma.data());
  backend.mass_matrix(q.data(), M.data());
  backend.inverse_dynamics(q.data(), v.data(), VecX<double>::Zero(nv).eval().data(), bias.data());
  using RowMajor = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
  const MatX<double> J = RowMajor(Jbuf.data(), rows, nv), Mm = RowMajor(M.data(), nv, nv);
  EXPECT_GT(Phi.cwiseAbs().maxCoeff(), 1e-4) << "the loops are open";
  // lambda from the equations of motion: J^T lambda = M qdd + bias - tau (J has full row rank).
  const VecX<double> residual_force = Mm * qdd + bias - tau;
  const VecX<double> lambda = J.transpose().colPivHouseholderQr().solve(residual_force);
  EXPECT_LT((J.transpose() * lambda - residual_force).norm(), 1e-9 * residual_force.norm()) << "a constraint force";
  const MatX<double> A = J * Mm.ldlt().solve(J.transpose());
  const VecX<double> a_ref = gamma - (2 / o.time_constant) * (J * v) - (1 / (o.time_constant * o.time_constant)) * Phi;
  const VecX<double> miss = J * qdd - a_ref;
  const VecX<double> predicted = -((1 - o.impedance) / o.impedance) * A.diagonal().cwiseProduct(lambda);
  EXPECT_LT((miss - predicted).norm(), 1e-7 * a_ref.norm()) << "miss " << miss.transpose() << "\npredicted " << predicted.transpose();
  EXPECT_GT(miss.norm(), 1e-3 * a_ref.norm()) << "soft: not the hard constraint";
}

}  // namespace
}  // namespace mbgen::test
