#pragma once
// Actuator <-> joint maps of drive linkages (the thesis' knee and ankle drive kinematics) on a
// backend's loops: the actuators are independent coordinates of the closed system, the output
// joints (the knee, the foot's pitch and roll) dependent ones of the same loops.
//   to_joints:    a -> o  the backend's closure_positions with the actuators set (on
//                         NAME::Backend the generated Newton), o read off the closed q;
//                         J = do/da: the velocity map's rows of the outputs, columns of the
//                         actuators (the generated velocity_map).
//   to_actuators: o -> a  Newton on o(a) = o_target with that Jacobian, warm-started from the
//                         actuators' entries of the q given: each iteration one closure, quadratic
//                         convergence near the solution; from afar the step is halved while the
//                         loops cannot close there or the error grows; J = da/do = (do/da)^-1.
// The runtime's TransmissionMap (algorithm/transmission_map.hpp) is the generic twin of the
// second direction on a Model partitioned with the outputs independent; this one needs nothing
// but the backend, so a controller on generated code commands its actuators with it.
//
// q (nq) carries the rest of the configuration and the warm start; it comes back closed. The
// coordinates are 1-DoF joints after a possible floating base (q index = v index + 1 with one,
// the v index without); the constructor checks that the backend has no other quaternion.
// Allocation-free after construction; the calls do not throw.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "mbgen/spatial/types.hpp"

namespace mbgen::control {

enum class MapStatus : int {
  converged = 0,
  not_converged = 1,  ///< the closure or the outer Newton did not reach its tolerance
  singular = 2,       ///< a linkage at a dead point: the closure, or do/da, is singular there
};

template <typename Backend> class ActuatorJointMap {
 public:
  using S = typename Backend::Scalar;

  /// actuator_v, output_v: v indices, as many outputs as actuators. Throws std::invalid_argument
  /// naming the problem: different counts, an actuator that is not an independent coordinate, an
  /// index out of range, a backend with quaternions besides a floating base.
  ActuatorJointMap(Backend backend, std::vector<int> actuator_v, std::vector<int> output_v)
      : backend_(std::move(backend)), actuator_v_(std::move(actuator_v)), output_v_(std::move(output_v)),
        n_(static_cast<int>(actuator_v_.size())), q_offset_(backend_.floating_base() ? 1 : 0) {
    const int nq = backend_.nq(), nv = backend_.nv(), ny = backend_.ny();
    if (nq - nv != q_offset_)
      throw std::invalid_argument("ActuatorJointMap: the backend has quaternion joints besides a floating base (nq - nv = " +
                                  std::to_string(nq - nv) + "): its q indices cannot follow from v indices");
    if (output_v_.size() != actuator_v_.size() || n_ == 0)
      throw std::invalid_argument("ActuatorJointMap: " + std::to_string(actuator_v_.size()) + " actuator(s) and " +
                                  std::to_string(output_v_.size()) + " output(s): a map needs as many of each, at least one");
    const int* independent = backend_.independent_v_index();
    for (int v : actuator_v_) {
      if (v < q_offset_ * 6 || v >= nv) throw std::invalid_argument("ActuatorJointMap: actuator coordinate " + std::to_string(v) + " out of range");
      const int* at = std::find(independent, independent + ny, v);
      if (at == independent + ny)
        throw std::invalid_argument("ActuatorJointMap: actuator coordinate " + std::to_string(v) +
                                    " is not an independent coordinate of the loops: closure_positions would move it");
      actuator_column_.push_back(static_cast<int>(at - independent));
    }
    for (int v : output_v_)
      if (v < q_offset_ * 6 || v >= nv) throw std::invalid_argument("ActuatorJointMap: output coordinate " + std::to_string(v) + " out of range");
    T_.assign(static_cast<std::size_t>(nv * ny), S(0));
    J_ = MatX<S>::Zero(n_, n_);
    lu_ = Eigen::PartialPivLU<MatX<S>>(n_);
    a_ = VecX<S>::Zero(n_), o_ = VecX<S>::Zero(n_), step_ = VecX<S>::Zero(n_), a_try_ = a_, o_try_ = o_;
    q_try_ = VecX<S>::Zero(nq);
  }

  int size() const { return n_; }

  /// o (n) = the output joints at the actuator positions a (n); q (nq) in/out. J (n x n,
  /// row-major, optional) = do/da.
  MapStatus to_joints(const S* a, S* q, S* o, S* J = nullptr) {
    for (int i = 0; i < n_; ++i) q[actuator_v_[static_cast<std::size_t>(i)] + q_offset_] = a[i];
    const int status = backend_.closure_positions(q);
    if (status != 0) return static_cast<MapStatus>(status);
    for (int i = 0; i < n_; ++i) o[i] = q[output_v_[static_cast<std::size_t>(i)] + q_offset_];
    if (J) {
      jacobian(q);
      for (int r = 0; r < n_; ++r)
        for (int c = 0; c < n_; ++c) J[r * n_ + c] = J_(r, c);
    }
    return MapStatus::converged;
  }

  /// a (n) = the actuator positions that put the output joints at o (n); q (nq) in/out, its
  /// actuator entries the warm start. J (n x n, row-major, optional) = da/do. `iterations`, if
  /// given, receives the outer Newton's steps.
  MapStatus to_actuators(const S* o, S* q, S* a, S* J = nullptr, S tolerance = default_tolerance(), int max_iterations = 20,
                         int* iterations = nullptr) {
    for (int i = 0; i < n_; ++i) a_[i] = q[actuator_v_[static_cast<std::size_t>(i)] + q_offset_];
    MapStatus status = to_joints(a_.data(), q, o_.data());
    S worst = error(o_, o);
    int k = 0;
    while (status == MapStatus::converged) {
      jacobian(q);
      lu_.compute(J_);
      if (!(std::abs(lu_.determinant()) > S(0))) {
        status = MapStatus::singular;
        break;
      }
      if (worst <= tolerance) break;
      if (k == max_iterations || !(worst == worst)) {
        status = MapStatus::not_converged;
        break;
      }
      ++k;
      for (int i = 0; i < n_; ++i) o_[i] -= o[i];
      step_ = lu_.solve(o_);
      // Backtracking: halve the step while the loops do not close there or the error grows (a
      // far start: the full step can leave the linkages' workspace).
      bool accepted = false;
      S t = S(1);
      for (int h = 0; h < 12 && !accepted; ++h, t *= S(0.5)) {
        for (int i = 0; i < q_try_.size(); ++i) q_try_[i] = q[i];
        a_try_ = a_ - t * step_;
        if (to_joints(a_try_.data(), q_try_.data(), o_try_.data()) != MapStatus::converged) continue;
        const S e = error(o_try_, o);
        if (!(e < worst)) continue;
        accepted = true;
        worst = e;
        a_ = a_try_;
        o_ = o_try_;
        for (int i = 0; i < q_try_.size(); ++i) q[i] = q_try_[i];
      }
      if (!accepted) status = MapStatus::not_converged;
    }
    if (iterations) *iterations = k;
    for (int i = 0; i < n_; ++i) a[i] = a_[i];
    if (status == MapStatus::converged && J) {
      for (int c = 0; c < n_; ++c) {  // da/do = (do/da)^-1, column by column
        step_.setZero();
        step_[c] = S(1);
        o_try_ = lu_.solve(step_);
        for (int r = 0; r < n_; ++r) J[r * n_ + c] = o_try_[r];
      }
    }
    return status;
  }

  /// On the outputs (rad, m): above what the closure's own tolerance (1e-12 in double, 2e-6 in
  /// float, on the loops' residual) leaves in them, so that Newton can reach it.
  static S default_tolerance() { return sizeof(S) == sizeof(float) ? S(1e-4) : S(1e-10); }

 private:
  S error(const VecX<S>& x, const S* target) const {
    S worst = S(0);
    for (int i = 0; i < n_; ++i) {
      const S e = std::abs(x[i] - target[i]);
      if (!(e <= worst)) worst = e;  // NaN propagates
    }
    return worst;
  }
  /// J_ = do/da at the closed q: the velocity map's output rows at the actuators' columns.
  void jacobian(const S* q) {
    const int ny = backend_.ny();
    backend_.velocity_map(q, T_.data());
    for (int r = 0; r < n_; ++r)
      for (int c = 0; c < n_; ++c)
        J_(r, c) = T_[static_cast<std::size_t>(output_v_[static_cast<std::size_t>(r)] * ny + actuator_column_[static_cast<std::size_t>(c)])];
  }

  Backend backend_;
  std::vector<int> actuator_v_, output_v_, actuator_column_;
  int n_, q_offset_;
  std::vector<S> T_;
  MatX<S> J_;
  Eigen::PartialPivLU<MatX<S>> lu_;
  VecX<S> a_, o_, step_, a_try_, o_try_, q_try_;
};

}  // namespace mbgen::control
