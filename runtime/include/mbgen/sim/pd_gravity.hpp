#pragma once
// PD control with gravity compensation, the controller the simulator's scenarios stand on
// (docs/simulation.md). On the closed system's independent coordinates (the actuated joints; a
// floating base's six are not actuated):
//   tau_y = Kp (q_ref - q) - Kd vy + (T^T g(q))_y,   g(q) = inverse_dynamics(q, 0, 0),
// written into the tree forces at the independent joints (zero elsewhere), which is where
// forward dynamics applies them. T^T g is the closed system's gravity: the closure forces do no
// work on motions that keep the loops closed.
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

  VecX<S>& target() { return q_ref_; }

 private:
  Backend backend_;
  VecX<S> q_ref_, kp_, kd_, zeros_, gravity_, gravity_y_, T_;
  double effort_limit_;
};

}  // namespace mbgen::sim
