#include "joint_map.hpp"

#include <algorithm>
#include <stdexcept>

namespace mbgen::peers {

JointMap::JointMap(const PinocchioRobot& pinocchio, const std::vector<std::string>& joint_names, bool floating, int nq, int nv)
    : pinocchio_nq_(pinocchio.nq()) {
  if (pinocchio.nq() != nq || pinocchio.nv() != nv)
    throw std::runtime_error("peer: Pinocchio's model has nq " + std::to_string(pinocchio.nq()) + ", nv " +
                             std::to_string(pinocchio.nv()) + " against mbgen's " + std::to_string(nq) + ", " + std::to_string(nv));
  const int base_q = floating ? 7 : 0, base_v = floating ? 6 : 0;
  for (int i = 0; i < base_q; ++i) pinocchio_q_.push_back(i);
  for (int i = 0; i < base_v; ++i) pinocchio_v_.push_back(i);
  for (std::size_t j = floating ? 1 : 0; j < joint_names.size(); ++j) {
    const PinocchioJointSlot slot = pinocchio.joint(joint_names[j]);
    if (slot.nv == 0) throw std::runtime_error("peer: Pinocchio's model has no joint " + joint_names[j]);
    if (slot.nq != 1 || slot.nv != 1)
      throw std::runtime_error("peer: Pinocchio's joint " + joint_names[j] + " has " + std::to_string(slot.nq) +
                               " coordinates; mbgen's has one");
    pinocchio_q_.push_back(slot.q);
    pinocchio_v_.push_back(slot.v);
  }
  if (static_cast<int>(pinocchio_q_.size()) != nq || static_cast<int>(pinocchio_v_.size()) != nv)
    throw std::runtime_error("peer: mbgen's joint names do not cover its nq and nv");
}

Eigen::VectorXd JointMap::q_to_pinocchio(const Eigen::VectorXd& q) const {
  Eigen::VectorXd out(pinocchio_nq_);
  for (std::size_t i = 0; i < pinocchio_q_.size(); ++i) out[pinocchio_q_[i]] = q[static_cast<int>(i)];
  return out;
}

Eigen::VectorXd JointMap::v_to_pinocchio(const Eigen::VectorXd& v) const {
  Eigen::VectorXd out(static_cast<int>(pinocchio_v_.size()));
  for (std::size_t i = 0; i < pinocchio_v_.size(); ++i) out[pinocchio_v_[i]] = v[static_cast<int>(i)];
  return out;
}

Eigen::VectorXd JointMap::v_from_pinocchio(const Eigen::VectorXd& v) const {
  Eigen::VectorXd out(static_cast<int>(pinocchio_v_.size()));
  for (std::size_t i = 0; i < pinocchio_v_.size(); ++i) out[static_cast<int>(i)] = v[pinocchio_v_[i]];
  return out;
}

Eigen::MatrixXd JointMap::matrix_from_pinocchio(const Eigen::MatrixXd& m) const {
  const int n = static_cast<int>(pinocchio_v_.size());
  Eigen::MatrixXd out(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) out(i, j) = m(pinocchio_v_[i], pinocchio_v_[j]);
  return out;
}

double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  const double scale = b.cwiseAbs().maxCoeff();
  return (a - b).cwiseAbs().maxCoeff() / std::max(scale, 1e-300);
}

}  // namespace mbgen::peers
