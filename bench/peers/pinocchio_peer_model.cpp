// PinocchioRobot: loading a URDF with Pinocchio's parser, and the joints' slots.
#include <stdexcept>

#include "pinocchio/parsers/urdf.hpp"
#include "pinocchio_peer_impl.hpp"

namespace mbgen::peers {
namespace {

const RevoluteChain* chain_of(const std::vector<RevoluteChain>& chains, const std::string& joint) {
  for (const RevoluteChain& c : chains)
    if (c.joint == joint) return &c;
  return nullptr;
}

// The parsed tree rebuilt joint by joint, each joint named in `chains` replaced by revolute joints
// about x, y (, z) at its origin; the closures' frames (the URDF's "closedloop*" links, which the
// parser turns into body frames) follow their joints.
pinocchio::Model with_chains(const pinocchio::Model& parsed, const std::vector<RevoluteChain>& chains) {
  using namespace pinocchio;
  Model m;
  m.name = parsed.name;
  std::vector<JointIndex> moved(parsed.njoints, 0);
  for (JointIndex j = 1; j < JointIndex(parsed.njoints); ++j) {
    const JointIndex parent = moved[parsed.parents[j]];
    const std::string& name = parsed.names[j];
    const RevoluteChain* chain = chain_of(chains, name);
    if (!chain) {
      moved[j] = m.addJoint(parent, parsed.joints[j], parsed.jointPlacements[j], name);
      m.appendBodyToJoint(moved[j], parsed.inertias[j], SE3::Identity());
      continue;
    }
    JointIndex last = m.addJoint(parent, JointModelRX(), parsed.jointPlacements[j], name + "_x");
    m.appendBodyToJoint(last, Inertia::Zero(), SE3::Identity());
    last = m.addJoint(last, JointModelRY(), SE3::Identity(), name + "_y");
    if (chain->axes == 3) {
      m.appendBodyToJoint(last, Inertia::Zero(), SE3::Identity());
      last = m.addJoint(last, JointModelRZ(), SE3::Identity(), name + "_z");
    }
    m.appendBodyToJoint(last, parsed.inertias[j], SE3::Identity());
    moved[j] = last;
  }
  for (const Frame& f : parsed.frames)
    if (f.type == BODY) m.addFrame(Frame(f.name, moved[f.parentJoint], 0, f.placement, BODY), false);
  return m;
}

}  // namespace

PinocchioRobot::PinocchioRobot(const std::string& urdf, bool floating, const std::vector<RevoluteChain>& chains)
    : impl_(std::make_unique<Impl>()) {
  pinocchio::Model parsed;
  try {
    if (floating)
      pinocchio::urdf::buildModel(urdf, pinocchio::JointModelFreeFlyer(), parsed);
    else
      pinocchio::urdf::buildModel(urdf, parsed);
  } catch (const std::exception& e) {
    throw std::runtime_error(urdf + ": Pinocchio cannot read it: " + e.what());
  }
  impl_->model = chains.empty() ? parsed : with_chains(parsed, chains);
  impl_->data = std::make_unique<pinocchio::Data>(impl_->model);
}

PinocchioRobot::~PinocchioRobot() = default;

int PinocchioRobot::nq() const { return impl_->model.nq; }
int PinocchioRobot::nv() const { return impl_->model.nv; }

PinocchioJointSlot PinocchioRobot::joint(const std::string& name) const {
  const pinocchio::Model& m = impl_->model;
  if (!m.existJointName(name)) return {};
  const auto id = m.getJointId(name);
  return {m.idx_qs[id], m.idx_vs[id], m.nqs[id], m.nvs[id]};
}

}  // namespace mbgen::peers
