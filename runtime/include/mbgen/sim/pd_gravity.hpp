#pragma once
// PD control with gravity compensation, the controller the simulator's scenarios stand on
// (docs/simulation.md). On the closed system's independent coordinates (the actuated joints; a
// floating base's six are not actuated):
//   tau_y = Kp (q_ref - q) - Kd vy + (T^T g(q))_y,   g(q) = inverse_dynamics(q, 0, 0),
// written into the tree forces at the independent joints (zero elsewhere), which is where
// forward dynamics applies them. T^T g is the closed system's gravity: the closure forces do no
// work on motions that keep the loops closed.
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "mbgen/spatial/types.hpp"

namespace mbgen::sim {

template <typename Backend> class PdGravityController {
 public:
  using S = typename Backend::Scalar;

  /// q_ref: nq, the pose to hold (its independent joints' entries are the targets); kp, kd: per
  /// independent coordinate (ny; the base's entries are ignored). `effort_limit` > 0 clamps
  /// each joint force to +-effort_limit.
  PdGravityController(Backend backend, VecX<S> q_ref, VecX<S> kp, VecX<S> kd, double effort_limit = 0)
      : backend_(std::move(backend)), q_ref_(std::move(q_ref)), kp_(std::move(kp)), kd_(std::move(kd)),
        effort_limit_(effort_limit) {
    const int nv = backend_.nv(), ny = backend_.ny();
    zeros_ = VecX<S>::Zero(nv), gravity_ = VecX<S>::Zero(nv), gravity_y_ = VecX<S>::Zero(ny), T_ = VecX<S>::Zero(nv * ny);
  }

  void operator()(double /*t*/, const S* q, const S* v, S* tau) {
    const int nv = backend_.nv(), ny = backend_.ny();
    const bool floating = backend_.floating_base();
    backend_.inverse_dynamics(q, zeros_.data(), zeros_.data(), gravity_.data());
    if (ny == nv) {
      gravity_y_ = gravity_;
    } else {
      backend_.velocity_map(q, T_.data());
      const Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> T(T_.data(), nv, ny);
      gravity_y_.noalias() = T.transpose() * gravity_;
    }
    for (int i = 0; i < nv; ++i) tau[i] = S(0);
    const int* independent = backend_.independent_v_index();
    for (int i = 0; i < ny; ++i) {
      const int j = independent[i];
      if (floating && j < 6) continue;
      const int qi = floating ? j + 1 : j;  // past the base every joint has one coordinate
      S f = kp_[i] * (q_ref_[qi] - q[qi]) - kd_[i] * v[j] + gravity_y_[i];
      if (effort_limit_ > 0) f = std::clamp(f, S(-effort_limit_), S(effort_limit_));
      tau[j] = f;
    }
  }

  /// Gains from a bandwidth: for each independent coordinate kp = w^2 m, kd = 2 zeta w m,
  /// w = 2 pi bandwidth_hz, with m its apparent inertia at q_ref, 1 / (M_y^-1)_ii (M_y = T^T M T):
  /// what the joint feels when the rest of the robot is free to react. So a light wrist on a
  /// floating robot and a roller-screw nut driving a shank through its linkage (tens of kg) are
  /// tuned alike, and a controller at rate f stays inside its zero-order-hold stability limit
  /// while w / f is small (0.25 at 40 Hz and 1 kHz).
  static PdGravityController from_bandwidth(Backend backend, VecX<S> q_ref, double bandwidth_hz, double damping_ratio = 1,
                                            double effort_limit = 0) {
    const int nv = backend.nv(), ny = backend.ny();
    VecX<S> M_buffer(nv * nv), T_buffer(nv * ny);
    backend.mass_matrix(q_ref.data(), M_buffer.data());
    backend.velocity_map(q_ref.data(), T_buffer.data());
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    using Map = Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
    const RowMajor M = Map(M_buffer.data(), nv, nv).template cast<double>();
    const RowMajor T = Map(T_buffer.data(), nv, ny).template cast<double>();
    const Eigen::MatrixXd My = T.transpose() * M * T;
    const Eigen::MatrixXd My_inverse = My.ldlt().solve(Eigen::MatrixXd::Identity(ny, ny));
    const double w = 2 * M_PI * bandwidth_hz;
    VecX<S> kp(ny), kd(ny);
    for (int i = 0; i < ny; ++i) {
      const double m = 1 / My_inverse(i, i);
      kp[i] = S(w * w * m);
      kd[i] = S(2 * damping_ratio * w * m);
    }
    return PdGravityController(std::move(backend), std::move(q_ref), std::move(kp), std::move(kd), effort_limit);
  }

  VecX<S>& target() { return q_ref_; }
  const VecX<S>& kp() const { return kp_; }
  const VecX<S>& kd() const { return kd_; }

 private:
  Backend backend_;
  VecX<S> q_ref_, kp_, kd_, zeros_, gravity_, gravity_y_, T_;
  double effort_limit_;
};

}  // namespace mbgen::sim
