// Derivatives of the forward dynamics under the compliant ground (runtime/include/mbgen/algorithm/
// contact_dynamics_derivatives.hpp) against independent derivatives, on every URDF of the suite
// with fixed and floating base, three spheres on each leaf and a tilted ground between their
// two middle heights (compliant_contact_cases.hpp: springs, damping and friction all acting):
//  - forward-mode dual numbers pushed through the generic contact_forward_dynamics (the
//    articulated-body algorithm with the ground's forces as body forces: another algorithm than
//    the joint forces J^T f these derivatives differentiate): 1e-11 relative, or 10 eps cond(M);
//  - central finite differences along `integrate`: 1e-6 (or eps cond(M) / h);
// and the values equal contact_forward_dynamics' (1e-12), the call allocates nothing.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <random>

#include "autodiff_reference.hpp"
#include "compliant_contact_cases.hpp"
#include "derivative_errors.hpp"
#include "malloc_guard.hpp"
#include "mbgen/algorithm/contact_dynamics_derivatives.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

double condition_number(const MatX<double>& M) {
  const VecX<double> s = Eigen::JacobiSVD<MatX<double>>(M).singularValues();
  return s[0] / s[s.size() - 1];
}

struct Jacobians {
  MatX<double> da_dq, da_dv, da_dtau;
};

Jacobians dual_jacobians(const Model& model, const CompliantScene& scene, const VecX<double>& q, const VecX<double>& v,
                         const VecX<double>& tau) {
  const int nv = model.nv();
  Data<Dual> data(model);
  Jacobians out{MatX<double>(nv, nv), MatX<double>(nv, nv), MatX<double>(nv, nv)};
  Dual ground[kGroundInputs], law[kLawInputs];
  for (int i = 0; i < kGroundInputs; ++i) ground[i] = Dual(scene.ground_inputs[i]);
  for (int i = 0; i < kLawInputs; ++i) law[i] = Dual(scene.law_inputs[i]);
  std::vector<Dual> outputs(kContactOutputs * scene.spheres.size());
  const VecX<Dual> qd = seeded_vector(q), vd = seeded_vector(v), taud = seeded_vector(tau);
  const auto pass = [&](const VecX<Dual>& qx, const VecX<Dual>& vx, const VecX<Dual>& tx) {
    return derivative_part(contact_forward_dynamics<Dual>(model, data, scene.spheres, scene.law.exponent, qx, vx, tx, ground, law,
                                                          outputs.data()));
  };
  for (int k = 0; k < nv; ++k) {
    out.da_dq.col(k) = pass(seeded_configuration(model, q, k), vd, taud);
    out.da_dv.col(k) = pass(qd, seeded_vector(v, k), taud);
    out.da_dtau.col(k) = pass(qd, vd, seeded_vector(tau, k));
  }
  return out;
}

class ContactDynamicsDerivativesTest : public ::testing::TestWithParam<UrdfCase> {
 protected:
  void SetUp() override {
    model = load_tree(GetParam().path, GetParam().base);
    std::mt19937_64 rng(70);
    scene = leaf_spheres(model, rng);
    q = random_configuration<double>(model, rng);
    v = random_vector<double>(model.nv(), rng, 0.5);  // slow enough that the damping does not lift the spheres
    tau = random_vector<double>(model.nv(), rng, 10.0);
    scene.cut_at(model, q);
  }
  void derivatives(Data<double>& data, ContactDynamicsDerivatives<double>& d, std::vector<double>& outputs) {
    outputs.resize(kContactOutputs * scene.spheres.size());
    contact_forward_dynamics_derivatives<double>(model, data, d, scene.spheres, scene.law.exponent, q, v, tau, scene.ground_inputs,
                                                 scene.law_inputs, outputs.data());
  }
  Model model;
  CompliantScene scene;
  VecX<double> q, v, tau;
};

TEST_P(ContactDynamicsDerivativesTest, MatchDualNumbers) {
  Data<double> data(model), other(model);
  ContactDynamicsDerivatives<double> d(model);
  std::vector<double> outputs, expected_outputs(kContactOutputs * scene.spheres.size());
  derivatives(data, d, outputs);
  int active = 0;
  for (std::size_t k = 0; k < scene.spheres.size(); ++k)
    active += Eigen::Map<const Vec3<double>>(&outputs[kContactOutputs * k + 4]).norm() > 0 ? 1 : 0;  // a force
  ASSERT_GT(active, 0);
  const VecX<double> a = contact_forward_dynamics<double>(model, other, scene.spheres, scene.law.exponent, q, v, tau,
                                                          scene.ground_inputs, scene.law_inputs, expected_outputs.data());
  // d.fd.ddq comes from M's factor, a from the articulated-body algorithm: compared weighted by M
  // (on 5bar_linkage the two differ by up to 1.2e-11 unweighted).
  EXPECT_LT(weighted_relative(crba<double>(model, other, q), d.fd.ddq, a), 1e-13);
  for (std::size_t i = 0; i < outputs.size(); ++i) EXPECT_NEAR(outputs[i], expected_outputs[i], 1e-12 * (1 + std::abs(outputs[i])));

  // The reference on the spheres in contact: the others' forces are zero near q, and a dual number
  // through the law's root at zero depth would carry 0 times infinity.
  CompliantScene touching = scene;
  touching.spheres.clear();
  for (std::size_t k = 0; k < scene.spheres.size(); ++k)
    if (outputs[kContactOutputs * k] > 0) touching.spheres.push_back(scene.spheres[k]);
  const Jacobians ref = dual_jacobians(model, touching, q, v, tau);
  const double condition = condition_number(crba<double>(model, other, q)), tolerance = std::max(1e-11, 10 * 2.2e-16 * condition);
  SCOPED_TRACE(std::to_string(active) + " of " + std::to_string(scene.spheres.size()) + " spheres in contact, condition number " +
               std::to_string(condition));
  EXPECT_LT(relative_error(d.fd.dddq_dq, ref.da_dq), tolerance);
  EXPECT_LT(relative_error(d.fd.dddq_dv, ref.da_dv), tolerance);
  EXPECT_LT(relative_error(d.fd.Minv, ref.da_dtau), tolerance);
  // The ground's part is not negligible: without it the derivatives are 100 times further off.
  const double floor = 1e-15;
  EXPECT_GT(relative_error(MatX<double>(d.fd.dddq_dq - d.fd.Minv * d.dtau_dq), ref.da_dq),
            100 * std::max(floor, relative_error(d.fd.dddq_dq, ref.da_dq)));
  EXPECT_GT(relative_error(MatX<double>(d.fd.dddq_dv - d.fd.Minv * d.dtau_dv), ref.da_dv),
            100 * std::max(floor, relative_error(d.fd.dddq_dv, ref.da_dv)));
}

// The tangent convention, by central differences along integrate.
TEST_P(ContactDynamicsDerivativesTest, MatchCentralDifferencesAlongIntegrate) {
  Data<double> data(model);
  ContactDynamicsDerivatives<double> d(model);
  std::vector<double> outputs;
  derivatives(data, d, outputs);
  const int nv = model.nv();
  MatX<double> aq(nv, nv), av(nv, nv);
  const auto at = [&](const VecX<double>& qx, const VecX<double>& vx) {
    return VecX<double>(contact_forward_dynamics<double>(model, data, scene.spheres, scene.law.exponent, qx, vx, tau,
                                                         scene.ground_inputs, scene.law_inputs, outputs.data()));
  };
  const double h = 1e-6, hv = 1e-5;
  for (int k = 0; k < nv; ++k) {
    const VecX<double> e = VecX<double>::Unit(nv, k);
    const CentralPair p = central_pair(model, q, e, h);
    aq.col(k) = (at(p.plus, v) - at(p.minus, v)) / (2 * h);
    av.col(k) = (at(q, v + hv * e) - at(q, v - hv * e)) / (2 * hv);
  }
  Data<double> other(model);
  const double condition = condition_number(crba<double>(model, other, q));
  SCOPED_TRACE("condition number " + std::to_string(condition));
  EXPECT_LT(relative_error(d.fd.dddq_dq, aq), std::max(1e-6, 2.2e-16 * condition / h));
  EXPECT_LT(relative_error(d.fd.dddq_dv, av), std::max(1e-6, 2.2e-16 * condition / hv));
}

TEST_P(ContactDynamicsDerivativesTest, AllocatesNothing) {
  Data<double> data(model);
  ContactDynamicsDerivatives<double> d(model);
  std::vector<double> outputs(kContactOutputs * scene.spheres.size());
  MallocGuard guard;
  derivatives(data, d, outputs);
  EXPECT_EQ(guard.count(), 0u);
}

INSTANTIATE_TEST_SUITE_P(AllUrdfs, ContactDynamicsDerivativesTest, ::testing::ValuesIn(all_urdf_cases()), urdf_case_name);

}  // namespace
}  // namespace mbgen::test
