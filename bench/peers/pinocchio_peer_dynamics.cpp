// PinocchioRobot: the tree algorithms and their derivatives.
#include "pinocchio/algorithm/aba-derivatives.hpp"
#include "pinocchio/algorithm/aba.hpp"
#include "pinocchio/algorithm/crba.hpp"
#include "pinocchio/algorithm/rnea-derivatives.hpp"
#include "pinocchio/algorithm/rnea.hpp"
#include "pinocchio_peer_impl.hpp"

namespace mbgen::peers {
namespace {

template <typename Matrix> Eigen::MatrixXd symmetric_from_upper(const Matrix& upper) {
  Eigen::MatrixXd full = upper;
  full.template triangularView<Eigen::StrictlyLower>() = upper.transpose().template triangularView<Eigen::StrictlyLower>();
  return full;
}

}  // namespace

const Eigen::VectorXd& PinocchioRobot::aba(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& tau) {
  return pinocchio::aba(impl_->model, *impl_->data, q, v, tau);
}

const Eigen::VectorXd& PinocchioRobot::rnea(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a) {
  return pinocchio::rnea(impl_->model, *impl_->data, q, v, a);
}

Eigen::MatrixXd PinocchioRobot::crba(const Eigen::VectorXd& q) { return symmetric_from_upper(crba_upper(q)); }

const Eigen::MatrixXd& PinocchioRobot::crba_upper(const Eigen::VectorXd& q) {
  return pinocchio::crba(impl_->model, *impl_->data, q);
}

void PinocchioRobot::aba_derivatives(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& tau) {
  pinocchio::computeABADerivatives(impl_->model, *impl_->data, q, v, tau);
}

void PinocchioRobot::rnea_derivatives(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a) {
  pinocchio::computeRNEADerivatives(impl_->model, *impl_->data, q, v, a);
}

const Eigen::VectorXd& PinocchioRobot::ddq() const { return impl_->data->ddq; }
const PinocchioRobot::RowMatrix& PinocchioRobot::ddq_dq() const { return impl_->data->ddq_dq; }
const PinocchioRobot::RowMatrix& PinocchioRobot::ddq_dv() const { return impl_->data->ddq_dv; }
Eigen::MatrixXd PinocchioRobot::minv() const { return symmetric_from_upper(impl_->data->Minv); }
const PinocchioRobot::RowMatrix& PinocchioRobot::dtau_dq() const { return impl_->data->dtau_dq; }
const PinocchioRobot::RowMatrix& PinocchioRobot::dtau_dv() const { return impl_->data->dtau_dv; }

}  // namespace mbgen::peers
