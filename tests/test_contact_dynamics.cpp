// contact_forward_dynamics (runtime/include/mbgen/algorithm/contact_dynamics.hpp): the ground's
// forces as external body forces of the articulated-body algorithm, against the same law mapped to
// the joints by contact_joint_forces (world-axes Jacobian columns, a different mapping) and solved
// by a second algorithm: a tree (TALOS on two soles, the plain recursion and the O(n^3) mass
// matrix solve) and a closed-loop robot (Lola on its feet, the recursion with sub-systems).
// Each robot is lowered 1-2 mm into a ground tilted by 0.05 rad about x, so that some spheres
// press and slip while others hang free.
#include <gtest/gtest.h>

#include <random>

#include "collision/contact_spheres.hpp"
#include "mbgen/algorithm/contact_dynamics.hpp"
#include "mbgen/algorithm/crba.hpp"
#include "mbgen/algorithm/rnea.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

gen::Description load(const std::string& urdf, const std::string& extras) {
  gen::LoadOptions options;
  options.extras_file = extras;
  options.base = gen::BaseType::Floating;
  return gen::load_description(urdf, options);
}

struct Inputs {
  double ground[kGroundInputs], law[kLawInputs];
  double exponent;
};

Inputs tilted_ground() {
  Inputs in;
  ContactParameters p;
  contact_inputs(GroundPlane::tilted_about_x(0.05), p, in.ground, in.law);
  in.exponent = p.exponent;
  return in;
}

/// The per-sphere outputs of both paths agree, and at least one sphere presses and one hangs free.
void expect_same_contacts(const VecX<double>& out, const VecX<double>& out_joint) {
  EXPECT_LT((out - out_joint).cwiseAbs().maxCoeff(), 1e-12 * out.cwiseAbs().maxCoeff());
  int pressing = 0, apart = 0;
  for (int k = 0; k < out.size() / kContactOutputs; ++k) (out[kContactOutputs * k] > 0 ? pressing : apart) += 1;
  EXPECT_GT(pressing, 0);
  EXPECT_GT(apart, 0);
}

TEST(ContactDynamics, TreeBodyForcesEqualTheMassMatrixSolveWithJointForces) {
  const gen::Description d =
      load(MBGEN_SHARED_ROBOTS "/talos/talos_reduced.urdf", MBGEN_SOURCE_DIR "/examples/data/talos_sim.yaml");
  ASSERT_TRUE(d.model.subsystems.empty());
  const std::vector<ContactSphere> spheres = gen::contact_spheres(d);
  const int nv = d.model.nv(), nc = static_cast<int>(spheres.size());
  const Inputs in = tilted_ground();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  Data<double> data(d.model), reference(d.model);
  for (int trial = 0; trial < 4; ++trial) {
    const VecX<double> q = sunk_into_ground(d, spheres, 2e-3);
    VecX<double> v(nv), tau(nv);
    for (int i = 0; i < nv; ++i) v[i] = 0.3 * unit(rng), tau[i] = 20 * unit(rng);
    VecX<double> out(kContactOutputs * nc), out_joint(out.size());
    const VecX<double> qdd =
        contact_forward_dynamics<double>(d.model, data, spheres, in.exponent, q, v, tau, in.ground, in.law, out.data());
    // The reference: tau + J^T f through the joint-space mapping, then M qdd = tau - C v - g.
    VecX<double> tau_total = tau;
    contact_joint_forces<double>(d.model, reference, spheres, in.exponent, q, v.data(), in.ground, in.law, tau_total.data(),
                                 out_joint.data());
    const MatX<double> M = crba<double>(d.model, reference, q);
    const VecX<double> bias = rnea<double>(d.model, reference, q, v, VecX<double>::Zero(nv));
    const VecX<double> qdd_ref = M.ldlt().solve(tau_total - bias);
    EXPECT_LT((qdd - qdd_ref).cwiseAbs().maxCoeff(), 1e-10 * qdd_ref.cwiseAbs().maxCoeff()) << trial;
    EXPECT_GT((tau_total - tau).cwiseAbs().maxCoeff(), 10.0) << "the ground did act";
    expect_same_contacts(out, out_joint);
  }
}

TEST(ContactDynamics, LoopBodyForcesEqualTheRecursionWithJointForces) {
  const gen::Description d = load(MBGEN_SOURCE_DIR "/robots/lola/lola.urdf", MBGEN_SOURCE_DIR "/robots/lola/lola.yaml");
  ASSERT_FALSE(d.model.subsystems.empty());
  const std::vector<ContactSphere> spheres = gen::contact_spheres(d);
  const int nv = d.model.nv(), nc = static_cast<int>(spheres.size());
  const Inputs in = tilted_ground();
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> unit(-1, 1);
  Data<double> data(d.model), reference(d.model);
  for (int trial = 0; trial < 4; ++trial) {
    const VecX<double> q = sunk_into_ground(d, spheres, 1e-3);
    const int ny = static_cast<int>(d.model.structure().independent_v.size());
    VecX<double> vy(ny), v(nv), tau(nv);
    for (int i = 0; i < ny; ++i) vy[i] = 0.3 * unit(rng);
    for (int i = 0; i < nv; ++i) tau[i] = 20 * unit(rng);
    full_velocities<double>(d.model, reference, q, vy, v);
    // Only the independent entries of v are read: garbage in the dependent ones changes nothing.
    VecX<double> v_garbage = v;
    for (const SubSystem& s : d.model.subsystems)
      for (int z : s.dependent) v_garbage[z] = 1e3;
    VecX<double> out(kContactOutputs * nc), out_joint(out.size());
    const VecX<double> qdd =
        contact_forward_dynamics<double>(d.model, data, spheres, in.exponent, q, v_garbage, tau, in.ground, in.law, out.data());
    VecX<double> tau_total = tau;
    contact_joint_forces<double>(d.model, reference, spheres, in.exponent, q, v.data(), in.ground, in.law, tau_total.data(),
                                 out_joint.data());
    forward_dynamics_loops_independent<double>(d.model, reference, q, vy, tau_total);
    EXPECT_LT((qdd - reference.ddq).cwiseAbs().maxCoeff(), 1e-10 * reference.ddq.cwiseAbs().maxCoeff()) << trial;
    expect_same_contacts(out, out_joint);
  }
}

}  // namespace
}  // namespace mbgen::test
