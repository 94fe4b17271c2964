// Derivatives of the forward dynamics with rigid contacts held (runtime/include/mbgen/algorithm/
// rigid_contact_derivatives.hpp) against independent derivatives:
//  - forward-mode dual numbers pushed through the generic rigid_contact_dynamics (exact to
//    round-off; q along q (+) eps e_k): 1e-11 relative, or 10 eps times the condition number of
//    the matrices they solve with where that is larger (derivative_tolerance);
//  - central finite differences along `integrate`: 1e-6, or their round-off eps cond / h;
// on every URDF of the suite with fixed and floating base (contacts on the leaves,
// rigid_contact_cases.hpp); the values equal rigid_contact_dynamics' and the call allocates nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <Eigen/SVD>
#include <random>

#include "autodiff_reference.hpp"
#include "malloc_guard.hpp"
#include "mbgen/algorithm/rigid_contact_derivatives.hpp"
#include "rigid_contact_cases.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

/// The larger 2-norm condition number of the matrices the derivatives solve with: M (P = M^-1 dr1)
/// and the system [M -J^T; J 0].
double solve_condition(const MatX<double>& M, const MatX<double>& J) {
  const int nv = static_cast<int>(M.rows()), m = static_cast<int>(J.rows());
  MatX<double> K = MatX<double>::Zero(nv + m, nv + m);
  K.topLeftCorner(nv, nv) = M;
  K.topRightCorner(nv, m) = -J.transpose();
  K.bottomLeftCorner(m, nv) = J;
  const VecX<double> sk = Eigen::JacobiSVD<MatX<double>>(K).singularValues();
  const VecX<double> sm = Eigen::JacobiSVD<MatX<double>>(M).singularValues();
  return std::max(sk[0] / sk[nv + m - 1], sm[0] / sm[nv - 1]);
}

/// The tolerance of a comparison of two exact derivatives in double: 1e-11 relative, or 10 eps
/// times the solves' condition number where that is larger (the parallel_legs models' light
/// links: 1e6 to 1e7; there a long-double dual-number reference shows the double dual numbers
/// and this file's functions both 3e-10 to 6e-10 off, the forward error any backward-stable
/// solve has).
double derivative_tolerance(double condition) { return std::max(1e-11, 10 * 2.2e-16 * condition); }

struct ContactJacobians {
  MatX<double> da_dq, da_dv, da_dtau, dlambda_dq, dlambda_dv, dlambda_dtau;
};

ContactJacobians dual_contact_jacobians(const Model& model, const std::vector<RigidContact>& contacts, const VecX<double>& q,
                                        const VecX<double>& v, const VecX<double>& tau) {
  const int nv = model.nv();
  Data<Dual> data(model);
  RigidContactWorkspace<Dual> ws(model, contacts);
  ContactJacobians out{MatX<double>(nv, nv), MatX<double>(nv, nv), MatX<double>(nv, nv),
                       MatX<double>(ws.m, nv), MatX<double>(ws.m, nv), MatX<double>(ws.m, nv)};
  const VecX<Dual> qd = seeded_vector(q), vd = seeded_vector(v), taud = seeded_vector(tau);
  const auto pass = [&](const VecX<Dual>& qx, const VecX<Dual>& vx, const VecX<Dual>& tx, MatX<double>& da,
                        MatX<double>& dlambda, int k) {
    rigid_contact_dynamics<Dual>(model, data, ws, qx, vx, tx);
    da.col(k) = derivative_part(ws.a);
    dlambda.col(k) = derivative_part(ws.lambda);
  };
  for (int k = 0; k < nv; ++k) {
    pass(seeded_configuration(model, q, k), vd, taud, out.da_dq, out.dlambda_dq, k);
    pass(qd, seeded_vector(v, k), taud, out.da_dv, out.dlambda_dv, k);
    pass(qd, vd, seeded_vector(tau, k), out.da_dtau, out.dlambda_dtau, k);
  }
  return out;
}

class RigidContactDerivativesTest : public ::testing::TestWithParam<UrdfCase> {};

TEST_P(RigidContactDerivativesTest, MatchDualNumbers) {
  std::mt19937_64 rng(64);
  Model model = load_tree(GetParam().path, GetParam().base);
  const std::vector<RigidContact> contacts = leaf_contacts(model, rng);
  if (contacts.empty()) GTEST_SKIP() << "no leaf with a chain of 3 or more coordinates";
  Data<double> data(model), other(model);
  RigidContactWorkspace<double> ws(model, contacts), values(model, contacts);
  RigidContactDerivatives<double> d(model, ws);
  for (int trial = 0; trial < 2; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    const VecX<double> v = random_vector<double>(model.nv(), rng, 2.0);
    const VecX<double> tau = random_vector<double>(model.nv(), rng, 10.0);
    rigid_contact_dynamics_derivatives<double>(model, data, ws, d, q, v, tau);
    ASSERT_EQ(ws.status, RigidContactStatus::Solved);
    rigid_contact_dynamics<double>(model, other, values, q, v, tau);
    EXPECT_EQ(ws.a, values.a);
    EXPECT_EQ(ws.lambda, values.lambda);

    const ContactJacobians ref = dual_contact_jacobians(model, contacts, q, v, tau);
    const MatX<double> M = crba<double>(model, other, q);
    const double condition = solve_condition(M, ws.J), tolerance = derivative_tolerance(condition);
    SCOPED_TRACE("trial " + std::to_string(trial) + ", condition number " + std::to_string(condition));
    EXPECT_LT(relative_error(d.da_dq, ref.da_dq), tolerance);
    EXPECT_LT(relative_error(d.da_dv, ref.da_dv), tolerance);
    EXPECT_LT(relative_error(d.da_dtau, ref.da_dtau), tolerance);
    EXPECT_LT(relative_error(d.dlambda_dq, ref.dlambda_dq), tolerance);
    EXPECT_LT(relative_error(d.dlambda_dv, ref.dlambda_dv), tolerance);
    EXPECT_LT(relative_error(d.dlambda_dtau, ref.dlambda_dtau), tolerance);
  }
}

// The tangent convention, by central differences along integrate (h = 1e-6 in q; in v and tau a
// larger step: a is quadratic in v and linear in tau).
TEST_P(RigidContactDerivativesTest, MatchCentralDifferencesAlongIntegrate) {
  std::mt19937_64 rng(65);
  Model model = load_tree(GetParam().path, GetParam().base);
  const std::vector<RigidContact> contacts = leaf_contacts(model, rng);
  if (contacts.empty()) GTEST_SKIP() << "no leaf with a chain of 3 or more coordinates";
  Data<double> data(model);
  RigidContactWorkspace<double> ws(model, contacts), values(model, contacts);
  RigidContactDerivatives<double> d(model, ws);
  const int nv = model.nv(), m = ws.m;
  const VecX<double> q = random_configuration<double>(model, rng);
  const VecX<double> v = random_vector<double>(nv, rng, 2.0);
  const VecX<double> tau = random_vector<double>(nv, rng, 10.0);
  rigid_contact_dynamics_derivatives<double>(model, data, ws, d, q, v, tau);
  MatX<double> aq(nv, nv), av(nv, nv), lq(m, nv), lv(m, nv);
  const auto at = [&](const VecX<double>& qx, const VecX<double>& vx) {
    rigid_contact_dynamics<double>(model, data, values, qx, vx, tau);
    VecX<double> out(nv + m);
    out << values.a, values.lambda;
    return out;
  };
  const double h = 1e-6, hv = 1e-3;
  for (int k = 0; k < nv; ++k) {
    const VecX<double> e = VecX<double>::Unit(nv, k);
    const CentralPair p = central_pair(model, q, e, h);
    const VecX<double> dq = (at(p.plus, v) - at(p.minus, v)) / (2 * h);
    const VecX<double> dv = (at(q, v + hv * e) - at(q, v - hv * e)) / (2 * hv);
    aq.col(k) = dq.head(nv), lq.col(k) = dq.tail(m);
    av.col(k) = dv.head(nv), lv.col(k) = dv.tail(m);
  }
  Data<double> other(model);
  const MatX<double> M = crba<double>(model, other, q);
  // Central differences: 1e-6 relative, or their round-off eps cond / h where that is larger.
  const double condition = solve_condition(M, ws.J);
  SCOPED_TRACE("condition number " + std::to_string(condition));
  EXPECT_LT(relative_error(d.da_dq, aq), std::max(1e-6, 2.2e-16 * condition / h));
  EXPECT_LT(relative_error(d.da_dv, av), std::max(1e-6, 2.2e-16 * condition / hv));
  EXPECT_LT(relative_error(d.dlambda_dq, lq), std::max(1e-6, 2.2e-16 * condition / h));
  EXPECT_LT(relative_error(d.dlambda_dv, lv), std::max(1e-6, 2.2e-16 * condition / hv));
}

TEST_P(RigidContactDerivativesTest, AllocatesNothing) {
  std::mt19937_64 rng(66);
  Model model = load_tree(GetParam().path, GetParam().base);
  const std::vector<RigidContact> contacts = leaf_contacts(model, rng);
  if (contacts.empty()) GTEST_SKIP() << "no leaf with a chain of 3 or more coordinates";
  Data<double> data(model);
  RigidContactWorkspace<double> ws(model, contacts);
  RigidContactDerivatives<double> d(model, ws);
  const VecX<double> q = random_configuration<double>(model, rng);
  const VecX<double> v = random_vector<double>(model.nv(), rng), tau = random_vector<double>(model.nv(), rng);
  MallocGuard guard;
  rigid_contact_dynamics_derivatives<double>(model, data, ws, d, q, v, tau);
  EXPECT_EQ(guard.count(), 0u);
}

INSTANTIATE_TEST_SUITE_P(AllUrdfs, RigidContactDerivativesTest, ::testing::ValuesIn(all_urdf_cases()), urdf_case_name);

}  // namespace
}  // namespace mbgen::test
