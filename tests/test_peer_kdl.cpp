// mbgen's generic runtime against orocos-kdl, a peer implementation that shares nothing with it:
// the KDL models are built from the URDF directly through urdfdom (tests/kdl_from_urdf.*), not
// from mbgen's Model, so loader mistakes (merged fixed joints, inertial frames, axes) show too.
//
// Compared, over 100 seeded random states per robot:
//  - mass matrix:       crba                      vs ChainDynParam::JntToMass (chain joints)
//                                                 and vs TreeIdSolver_RNE columns (all joints)
//  - inverse dynamics:  rnea                      vs ChainIdSolver_RNE (chain joints)
//                                                 and vs TreeIdSolver_RNE (all joints)
//  - Jacobian:          frame_jacobian(tip, LocalWorldAligned) vs ChainJntToJacSolver
//  - forward dynamics:  aba                       vs ChainFdSolver_RNE
//
// Joints off the chain (panda's two finger joints): KDL's chain from the base to the hand leaves
// the fingers out, so its dynamics would lack their mass. The chain used here has the finger
// links welded onto the hand at the state's finger positions (kdl_chain_with_welded_branches).
// With the fingers at rest (v = a = 0 on the finger joints) the full model's arm block of M and
// its arm torques are then exactly the welded chain's: the fingers move rigidly with the hand.
// The finger rows themselves are checked against the full KDL tree (TreeIdSolver_RNE), with the
// fingers moving. Gravity is the model's, (0, 0, -9.81), on both sides.
#include <gtest/gtest.h>

#include <kdl/chaindynparam.hpp>
#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/jntspaceinertiamatrix.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <algorithm>
#include <cstdio>
#include <random>

#include "kdl_from_urdf.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

// 1e-9 relative (||a - b|| / max(1, ||b||)), as the foundation issue asks. Both sides are
// O(n) recursions in double on 7-9 DoF arms, so round-off is ~1e-14 (DESIGN.md: KDL agrees to
// ~1e-14 on arms); the margin of five orders only absorbs the conditioning of the forward
// dynamics (M^-1 amplifies round-off by cond(M), ~1e3-1e5 here). A modelling mistake (an inertia
// left in its inertial frame, a wrong axis sign, a lost mass) shows as >= 1e-4.
constexpr double kTol = 1e-9;
constexpr int kStates = 100;

struct PeerCase {
  std::string name;
  std::string urdf;
  std::string root;  ///< the URDF root link: mbgen's world for a fixed base
  std::string tip;   ///< end of the KDL chain; its frame is the Jacobian's
};
void PrintTo(const PeerCase& c, std::ostream* os) { *os << c.name; }

class PeerKdl : public ::testing::TestWithParam<PeerCase> {
 protected:
  void SetUp() override {
    const PeerCase& c = GetParam();
    model_ = load_tree(shared_robot(c.urdf), gen::BaseType::Fixed);
    tree_ = peer::kdl_tree_from_urdf_file(shared_robot(c.urdf));
    const KDL::Chain chain = peer::kdl_chain_with_welded_branches(tree_, c.root, c.tip);
    for (const std::string& name : peer::kdl_chain_joint_names(chain)) {
      auto j = model_.find_joint(name);
      ASSERT_TRUE(j) << "KDL chain joint '" << name << "' is not in mbgen's model";
      chain_v_.push_back(model_.joint(*j).idx_v);
    }
    tree_index_ = peer::kdl_tree_joint_indices(tree_);
    ASSERT_EQ(static_cast<int>(tree_index_.size()), model_.nv()) << "the KDL tree and mbgen differ in DoF";
    for (int j = 1; j < model_.num_joints(); ++j) {
      const Joint& joint = model_.joint(JointIndex(j));
      ASSERT_EQ(joint.nv, 1);
      ASSERT_EQ(joint.idx_q, joint.idx_v);
      ASSERT_TRUE(tree_index_.count(joint.name)) << "mbgen joint '" << joint.name << "' is not in the KDL tree";
      if (std::find(chain_v_.begin(), chain_v_.end(), joint.idx_v) == chain_v_.end()) off_chain_.push_back(j);
    }
    grav_ = KDL::Vector(model_.gravity.x(), model_.gravity.y(), model_.gravity.z());
  }

  /// The chain with the off-chain joints welded at their positions in q.
  KDL::Chain chain_at(const VecX<double>& q) const {
    std::map<std::string, double> off_q;
    for (int j : off_chain_) off_q[model_.joint(JointIndex(j)).name] = q[model_.joint(JointIndex(j)).idx_q];
    return peer::kdl_chain_with_welded_branches(tree_, GetParam().root, GetParam().tip, off_q);
  }
  KDL::JntArray to_chain(const VecX<double>& x) const {
    KDL::JntArray out(chain_v_.size());
    for (std::size_t k = 0; k < chain_v_.size(); ++k) out(k) = x[chain_v_[k]];
    return out;
  }
  VecX<double> chain_rows(const VecX<double>& x) const {
    VecX<double> out(chain_v_.size());
    for (std::size_t k = 0; k < chain_v_.size(); ++k) out[k] = x[chain_v_[k]];
    return out;
  }
  MatX<double> chain_block(const MatX<double>& M) const {
    MatX<double> out(chain_v_.size(), chain_v_.size());
    for (std::size_t r = 0; r < chain_v_.size(); ++r)
      for (std::size_t c = 0; c < chain_v_.size(); ++c) out(r, c) = M(chain_v_[r], chain_v_[c]);
    return out;
  }
  KDL::JntArray to_tree(const VecX<double>& x) const {
    KDL::JntArray out(model_.nv());
    for (int j = 1; j < model_.num_joints(); ++j) out(tree_index_.at(model_.joint(JointIndex(j)).name)) = x[model_.joint(JointIndex(j)).idx_v];
    return out;
  }
  VecX<double> from_tree(const KDL::JntArray& x) const {
    VecX<double> out(model_.nv());
    for (int j = 1; j < model_.num_joints(); ++j) out[model_.joint(JointIndex(j)).idx_v] = x(tree_index_.at(model_.joint(JointIndex(j)).name));
    return out;
  }
  /// A random velocity or acceleration that is zero on the off-chain joints.
  VecX<double> chain_only(VecX<double> x) const {
    for (int j : off_chain_) x[model_.joint(JointIndex(j)).idx_v] = 0.0;
    return x;
  }

  Model model_;
  KDL::Tree tree_;
  std::vector<int> chain_v_;              ///< mbgen v index of each chain joint, in chain order
  std::vector<int> off_chain_;            ///< mbgen joints not on the chain
  std::map<std::string, unsigned> tree_index_;
  KDL::Vector grav_;
};

TEST_P(PeerKdl, MassMatrix) {
  Data<double> data(model_);
  std::mt19937_64 rng(7);
  KDL::TreeIdSolver_RNE tree_id(tree_, KDL::Vector::Zero());  // gravity off: RNE(q, 0, e_i) = M e_i
  const int n = model_.nv();
  KDL::JntArray zero(n), e(n), column(n);
  double worst_chain = 0, worst_tree = 0;
  for (int trial = 0; trial < kStates; ++trial) {
    const VecX<double> q = random_configuration<double>(model_, rng);
    const MatX<double> M = crba<double>(model_, data, q);

    const KDL::Chain chain = chain_at(q);
    KDL::ChainDynParam dyn(chain, grav_);
    KDL::JntSpaceInertiaMatrix H(chain.getNrOfJoints());
    ASSERT_EQ(dyn.JntToMass(to_chain(q), H), 0);
    worst_chain = std::max(worst_chain, relative_error(chain_block(M), MatX<double>(H.data)));

    const KDL::JntArray q_tree = to_tree(q);
    MatX<double> M_tree(n, n);
    for (int c = 0; c < n; ++c) {
      VecX<double> unit = VecX<double>::Zero(n);
      unit[c] = 1.0;
      e = to_tree(unit);
      ASSERT_EQ(tree_id.CartToJnt(q_tree, zero, e, KDL::WrenchMap(), column), 0);
      M_tree.col(c) = from_tree(column);
    }
    worst_tree = std::max(worst_tree, relative_error(M, M_tree));
  }
  std::printf("  %s mass matrix: worst relative error %.2e (chain), %.2e (tree)\n", GetParam().name.c_str(),
              worst_chain, worst_tree);
  EXPECT_LT(worst_chain, kTol);
  EXPECT_LT(worst_tree, kTol);
}

TEST_P(PeerKdl, InverseDynamics) {
  Data<double> data(model_);
  std::mt19937_64 rng(11);
  KDL::TreeIdSolver_RNE tree_id(tree_, grav_);
  KDL::JntArray tau_tree(model_.nv());
  double worst_chain = 0, worst_tree = 0;
  for (int trial = 0; trial < kStates; ++trial) {
    const VecX<double> q = random_configuration<double>(model_, rng);
    // Chain: off-chain joints at rest, so they move rigidly with the segment they hang from.
    const VecX<double> v = chain_only(random_vector<double>(model_.nv(), rng, 2.0));
    const VecX<double> a = chain_only(random_vector<double>(model_.nv(), rng, 5.0));
    const VecX<double> tau = rnea<double>(model_, data, q, v, a);
    const KDL::Chain chain = chain_at(q);
    KDL::ChainIdSolver_RNE chain_id(chain, grav_);
    KDL::JntArray tau_kdl(chain.getNrOfJoints());
    ASSERT_EQ(chain_id.CartToJnt(to_chain(q), to_chain(v), to_chain(a),
                                 KDL::Wrenches(chain.getNrOfSegments(), KDL::Wrench::Zero()), tau_kdl),
              0);
    worst_chain = std::max(worst_chain, relative_error(chain_rows(tau), VecX<double>(tau_kdl.data)));

    // Tree: every joint moving.
    const VecX<double> v_all = random_vector<double>(model_.nv(), rng, 2.0);
    const VecX<double> a_all = random_vector<double>(model_.nv(), rng, 5.0);
    const VecX<double> tau_all = rnea<double>(model_, data, q, v_all, a_all);
    ASSERT_EQ(tree_id.CartToJnt(to_tree(q), to_tree(v_all), to_tree(a_all), KDL::WrenchMap(), tau_tree), 0);
    worst_tree = std::max(worst_tree, relative_error(tau_all, from_tree(tau_tree)));
  }
  std::printf("  %s inverse dynamics: worst relative error %.2e (chain), %.2e (tree)\n", GetParam().name.c_str(),
              worst_chain, worst_tree);
  EXPECT_LT(worst_chain, kTol);
  EXPECT_LT(worst_tree, kTol);
}

TEST_P(PeerKdl, Jacobian) {
  Data<double> data(model_);
  std::mt19937_64 rng(13);
  const FrameIndex tip = model_.frame_index(GetParam().tip);
  MatX<double> J(6, model_.nv());
  double worst = 0, worst_off_chain = 0;
  for (int trial = 0; trial < kStates; ++trial) {
    const VecX<double> q = random_configuration<double>(model_, rng);
    compute_joint_jacobians<double>(model_, data, q);
    // KDL: velocity of the tip origin and angular velocity, in the chain's base (world) axes,
    // [linear; angular] like mbgen's LocalWorldAligned.
    frame_jacobian<double>(model_, data, tip, ReferenceFrame::LocalWorldAligned, J);
    const KDL::Chain chain = chain_at(q);
    KDL::ChainJntToJacSolver jac_solver(chain);
    KDL::Jacobian J_kdl(chain.getNrOfJoints());
    ASSERT_EQ(jac_solver.JntToJac(to_chain(q), J_kdl), 0);
    MatX<double> J_chain(6, chain_v_.size());
    for (std::size_t k = 0; k < chain_v_.size(); ++k) J_chain.col(k) = J.col(chain_v_[k]);
    worst = std::max(worst, relative_error(J_chain, MatX<double>(J_kdl.data)));
    for (int j : off_chain_) worst_off_chain = std::max(worst_off_chain, J.col(model_.joint(JointIndex(j)).idx_v).norm());
  }
  std::printf("  %s Jacobian: worst relative error %.2e\n", GetParam().name.c_str(), worst);
  EXPECT_LT(worst, kTol);
  EXPECT_EQ(worst_off_chain, 0.0) << "joints that do not support the tip must have zero columns";
}

TEST_P(PeerKdl, ForwardDynamics) {
  Data<double> data(model_);
  std::mt19937_64 rng(17);
  double worst = 0;
  for (int trial = 0; trial < kStates; ++trial) {
    const VecX<double> q = random_configuration<double>(model_, rng);
    const VecX<double> v = chain_only(random_vector<double>(model_.nv(), rng, 2.0));
    const VecX<double> tau_chain = random_vector<double>(chain_v_.size(), rng, 20.0);
    const KDL::Chain chain = chain_at(q);
    KDL::ChainFdSolver_RNE fd(chain, grav_);
    KDL::JntArray tau_kdl(chain.getNrOfJoints()), ddq_kdl(chain.getNrOfJoints());
    tau_kdl.data = tau_chain;
    ASSERT_EQ(fd.CartToJnt(to_chain(q), to_chain(v), tau_kdl,
                           KDL::Wrenches(chain.getNrOfSegments(), KDL::Wrench::Zero()), ddq_kdl),
              0);
    // mbgen moves the off-chain joints too: give them the forces that hold them at rest when the
    // chain accelerates as KDL says (the finger rows of RNEA at [ddq_kdl; 0]). ABA must then
    // return [ddq_kdl; 0]. With no off-chain joints this is plain aba(q, v, tau) = ddq_kdl.
    VecX<double> ddq_expected = VecX<double>::Zero(model_.nv());
    for (std::size_t k = 0; k < chain_v_.size(); ++k) ddq_expected[chain_v_[k]] = ddq_kdl(k);
    VecX<double> tau = rnea<double>(model_, data, q, v, ddq_expected);
    for (std::size_t k = 0; k < chain_v_.size(); ++k) tau[chain_v_[k]] = tau_chain[k];
    const VecX<double> ddq = aba<double>(model_, data, q, v, tau);
    worst = std::max(worst, relative_error(ddq, ddq_expected));
  }
  std::printf("  %s forward dynamics: worst relative error %.2e\n", GetParam().name.c_str(), worst);
  EXPECT_LT(worst, kTol);
}

INSTANTIATE_TEST_SUITE_P(
    Arms, PeerKdl,
    ::testing::Values(PeerCase{"iiwa14", "iiwa14/iiwa14_primitive_collision.urdf", "base", "iiwa_link_ee"},
                      PeerCase{"panda", "panda/panda.urdf", "panda_link0", "panda_hand_tcp"}),
    [](const auto& info) { return info.param.name; });

// Floating base: KDL has none, so kdl_floating_tree_from_urdf_file puts six virtual joints
// (x, y, z, roll, pitch, yaw) under the root link, as KDL users do (and as the benchmarks' `kdl`
// inverse dynamics on hyq and talos does). With the base at the world origin, unrotated and at
// rest, the virtual joints' forces are the wrench on the base at its origin in world axes = base
// axes: mbgen's floating-base rows of tau. The leg and arm joints move at random. Same 1e-9.
class PeerKdlFloating : public ::testing::TestWithParam<PeerCase> {};

TEST_P(PeerKdlFloating, InverseDynamicsAtBaseRest) {
  const Model model = load_tree(shared_robot(GetParam().urdf), gen::BaseType::Floating);
  ASSERT_TRUE(model.floating_base());
  const KDL::Tree tree = peer::kdl_floating_tree_from_urdf_file(shared_robot(GetParam().urdf));
  const std::map<std::string, unsigned> index = peer::kdl_tree_joint_indices(tree);
  ASSERT_EQ(static_cast<int>(index.size()), model.nv()) << "six virtual joints + the robot's joints";
  const char* base_joints[] = {"floating_x", "floating_y", "floating_z", "floating_rx", "floating_ry", "floating_rz"};
  std::vector<unsigned> tree_of_v(model.nv());  // KDL index of each mbgen v entry
  for (int k = 0; k < 6; ++k) tree_of_v[k] = index.at(base_joints[k]);
  for (int j = 2; j < model.num_joints(); ++j) tree_of_v[model.joint(JointIndex(j)).idx_v] = index.at(model.joint(JointIndex(j)).name);
  auto to_tree = [&](const VecX<double>& x) {  // x has nv entries (base entries zero here)
    KDL::JntArray out(model.nv());
    for (int k = 0; k < model.nv(); ++k) out(tree_of_v[k]) = x[k];
    return out;
  };
  Data<double> data(model);
  KDL::TreeIdSolver_RNE solver(tree, KDL::Vector(model.gravity.x(), model.gravity.y(), model.gravity.z()));
  KDL::JntArray tau_kdl(model.nv());
  std::mt19937_64 rng(19);
  double worst = 0;
  for (int trial = 0; trial < kStates; ++trial) {
    VecX<double> q = random_configuration<double>(model, rng);
    q.head<7>() << 0, 0, 0, 0, 0, 0, 1;  // base at the world origin, unrotated
    VecX<double> v = random_vector<double>(model.nv(), rng, 2.0), a = random_vector<double>(model.nv(), rng, 5.0);
    v.head<6>().setZero();
    a.head<6>().setZero();
    VecX<double> q_v(model.nv());  // joint positions in v layout (base entries zero)
    q_v.head<6>().setZero();
    q_v.tail(model.nv() - 6) = q.tail(model.nq() - 7);
    const VecX<double> tau = rnea<double>(model, data, q, v, a);
    ASSERT_EQ(solver.CartToJnt(to_tree(q_v), to_tree(v), to_tree(a), KDL::WrenchMap(), tau_kdl), 0);
    VecX<double> tau_from_kdl(model.nv());
    for (int k = 0; k < model.nv(); ++k) tau_from_kdl[k] = tau_kdl(tree_of_v[k]);
    worst = std::max(worst, relative_error(tau, tau_from_kdl));
  }
  std::printf("  %s floating-base inverse dynamics: worst relative error %.2e\n", GetParam().name.c_str(), worst);
  EXPECT_LT(worst, kTol);
}

INSTANTIATE_TEST_SUITE_P(
    Legged, PeerKdlFloating,
    ::testing::Values(PeerCase{"hyq", "hyq/hyq_no_sensors.urdf", "", ""},
                      PeerCase{"talos", "talos/talos_reduced.urdf", "", ""}),
    [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace mbgen::test
