// PinocchioRobot: closed loops as 6-D rigid constraints, and pinocchio::constraintDynamics.
#include <algorithm>
#include <stdexcept>

#include "pinocchio/algorithm/constrained-dynamics.hpp"
#include "pinocchio/algorithm/kinematics.hpp"
#include "pinocchio/spatial/explog.hpp"
#include "pinocchio_peer_impl.hpp"

namespace mbgen::peers {

void PinocchioRobot::add_closure(const std::string& frame_a, const std::string& frame_b) {
  const pinocchio::Model& m = impl_->model;
  for (const std::string& f : {frame_a, frame_b})
    if (!m.existFrame(f)) throw std::runtime_error("Pinocchio's model of " + m.name + " has no frame " + f);
  const pinocchio::Frame& a = m.frames[m.getFrameId(frame_a)];
  const pinocchio::Frame& b = m.frames[m.getFrameId(frame_b)];
  impl_->closures.emplace_back(pinocchio::CONTACT_6D, m, a.parentJoint, a.placement, b.parentJoint, b.placement,
                               pinocchio::LOCAL);
  impl_->closure_data.emplace_back(impl_->closures.back());
  impl_->constraints_initialised = false;
}

const Eigen::VectorXd& PinocchioRobot::constraint_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                                           const Eigen::VectorXd& tau, bool tight) {
  Impl& p = *impl_;
  if (!p.constraints_initialised) {
    pinocchio::initConstraintDynamics(p.model, *p.data, p.closures);
    p.constraints_initialised = true;
  }
  pinocchio::ProximalSettings& settings = tight ? p.tight : p.defaults;
  const Eigen::VectorXd& ddq = pinocchio::constraintDynamics(p.model, *p.data, q, v, tau, p.closures, p.closure_data, settings);
  p.last_iterations = settings.iter;
  return ddq;
}

int PinocchioRobot::last_proximal_iterations() const { return impl_->last_iterations; }

double PinocchioRobot::closure_error(const Eigen::VectorXd& q) {
  Impl& p = *impl_;
  pinocchio::forwardKinematics(p.model, *p.data, q);
  double error = 0;
  for (const pinocchio::RigidConstraintModel& c : p.closures) {
    const pinocchio::SE3 a = p.data->oMi[c.joint1_id] * c.joint1_placement;
    const pinocchio::SE3 b = p.data->oMi[c.joint2_id] * c.joint2_placement;
    error = std::max(error, pinocchio::log6(a.actInv(b)).toVector().cwiseAbs().maxCoeff());
  }
  return error;
}

}  // namespace mbgen::peers
