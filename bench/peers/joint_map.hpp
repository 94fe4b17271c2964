#pragma once
// mbgen's coordinates against Pinocchio's: the same joints, matched by name, in each library's
// own order. Both put a floating base first as q = [x y z qx qy qz qw], v = [v_B w_B] in base
// coordinates (mbgen's header conventions; Pinocchio's JointModelFreeFlyer), so the base maps
// one to one and every other joint is a 1-DoF joint found by its name.
#include <Eigen/Core>

#include <string>
#include <vector>

#include "pinocchio_peer.hpp"

namespace mbgen::peers {

class JointMap {
 public:
  /// `joint_names`: the generated header's, in q and v order (a floating base's joint first).
  /// Throws std::runtime_error naming a joint Pinocchio's model lacks or gives more than one
  /// coordinate, and the sizes when they differ.
  JointMap(const PinocchioRobot& pinocchio, const std::vector<std::string>& joint_names, bool floating, int nq, int nv);

  Eigen::VectorXd q_to_pinocchio(const Eigen::VectorXd& q) const;
  Eigen::VectorXd v_to_pinocchio(const Eigen::VectorXd& v) const;
  Eigen::VectorXd v_from_pinocchio(const Eigen::VectorXd& v) const;
  /// An nv x nv matrix of Pinocchio's (rows and columns in its v order) in mbgen's order.
  Eigen::MatrixXd matrix_from_pinocchio(const Eigen::MatrixXd& m) const;

 private:
  std::vector<int> pinocchio_q_;  // for each of mbgen's q entries, Pinocchio's
  std::vector<int> pinocchio_v_;  // for each of mbgen's v entries, Pinocchio's
  int pinocchio_nq_;
};

/// max |a - b| / max |b|: the error of a against the reference b, relative to b's size.
double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

}  // namespace mbgen::peers
