#pragma once
// Configuration space: neutral and random configurations, integration on the manifold (the
// floating base's quaternion), and the time derivative of q for integrators in ambient space.
#include <cmath>
#include <random>

#include "mbgen/joint.hpp"

namespace mbgen {

/// Neutral configuration: zero joint angles, base at the origin with identity orientation.
template <typename S> VecX<S> neutral_configuration(const Model& model) {
  VecX<S> q = VecX<S>::Zero(model.nq());
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    if (joint.type == JointType::Floating) q[joint.idx_q + 6] = S(1);
  }
  return q;
}

/// Seeded random configuration: bounded joints uniform within their limits, unbounded revolute
/// joints in [-pi, pi], unbounded prismatic joints in [-1, 1] m, the floating base uniform in a
/// unit box with a uniformly random orientation.
template <typename S, typename Rng> VecX<S> random_configuration(const Model& model, Rng& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  VecX<S> q(model.nq());
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    S* qj = q.data() + joint.idx_q;
    switch (joint.type) {
      case JointType::Revolute:
      case JointType::Prismatic:
        if (joint.bounded && joint.upper > joint.lower) {
          qj[0] = S(joint.lower + (joint.upper - joint.lower) * (0.5 + 0.5 * unit(rng)));
        } else {
          qj[0] = S((joint.type == JointType::Revolute ? M_PI : 1.0) * unit(rng));
        }
        break;
      case JointType::Floating: {
        for (int k = 0; k < 3; ++k) qj[k] = S(unit(rng));
        Eigen::Vector4d quat(gauss(rng), gauss(rng), gauss(rng), gauss(rng));
        quat.normalize();
        for (int k = 0; k < 4; ++k) qj[3 + k] = S(quat[k]);
        break;
      }
    }
  }
  return q;
}

/// Seeded random vector of size n, entries uniform in [-scale, scale].
template <typename S, typename Rng> VecX<S> random_vector(int n, Rng& rng, double scale = 1.0) {
  std::uniform_real_distribution<double> unit(-scale, scale);
  VecX<S> x(n);
  for (int k = 0; k < n; ++k) x[k] = S(unit(rng));
  return x;
}

namespace detail {
/// Hamilton product of quaternions stored (x, y, z, w).
template <typename S> Eigen::Matrix<S, 4, 1> quat_multiply(const Eigen::Matrix<S, 4, 1>& a, const Eigen::Matrix<S, 4, 1>& b) {
  Eigen::Matrix<S, 4, 1> r;
  r << a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],  //
      a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],   //
      a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],   //
      a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2];
  return r;
}
}  // namespace detail

/// q (+) v: the configuration reached from q by moving with constant velocity v for unit time
/// (exact exponential map for the floating base, whose v is a body twist). Result in q_out.
template <typename S>
void integrate(const Model& model, const Eigen::Ref<const VecX<S>>& q, const Eigen::Ref<const VecX<S>>& v,
               Eigen::Ref<VecX<S>> q_out) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    const S* qj = q.data() + joint.idx_q;
    const S* vj = v.data() + joint.idx_v;
    S* out = q_out.data() + joint.idx_q;
    if (joint.type != JointType::Floating) {
      out[0] = qj[0] + vj[0];
      continue;
    }
    const Vec3<S> lin(vj[0], vj[1], vj[2]);
    const Vec3<S> w(vj[3], vj[4], vj[5]);
    const S theta = w.norm();
    const Mat3<S> wx = skew<S>(w);
    // p += R_WB V(w) lin, with V = I + (1 - cos t)/t^2 [w] + (t - sin t)/t^3 [w]^2.
    S a, b, half_sinc;
    if (theta < S(1e-4)) {
      const S t2 = theta * theta;
      a = S(0.5) - t2 / S(24);
      b = S(1) / S(6) - t2 / S(120);
      half_sinc = S(0.5) - t2 / S(48);
    } else {
      a = (S(1) - cos(theta)) / (theta * theta);
      b = (theta - sin(theta)) / (theta * theta * theta);
      half_sinc = sin(theta / S(2)) / theta;
    }
    const Mat3<S> V = Mat3<S>::Identity() + a * wx + b * wx * wx;
    const Eigen::Matrix<S, 4, 1> quat(qj[3], qj[4], qj[5], qj[6]);
    const Mat3<S> R = quaternion_to_rotation<S>(quat[0], quat[1], quat[2], quat[3]);
    const Vec3<S> dp = R * (V * lin);
    Eigen::Matrix<S, 4, 1> dq;
    dq << half_sinc * w, cos(theta / S(2));
    Eigen::Matrix<S, 4, 1> qn = detail::quat_multiply<S>(quat, dq);
    qn /= qn.norm();
    for (int k = 0; k < 3; ++k) out[k] = qj[k] + dp[k];
    for (int k = 0; k < 4; ++k) out[3 + k] = qn[k];
  }
}

/// q1 (-) q0: the velocity v (nv) with integrate(q0, v) = q1, the inverse of integrate (the
/// logarithm of the floating base's relative pose q0^-1 q1, body twist in q0's frame, the rotation
/// the shorter way round: |angle| <= pi). The tangent space the dynamics' derivatives are taken in
/// (rnea_derivatives.hpp): d/dq f along delta is the derivative of f(integrate(q, delta)).
template <typename S>
void difference(const Model& model, const Eigen::Ref<const VecX<S>>& q0, const Eigen::Ref<const VecX<S>>& q1,
                Eigen::Ref<VecX<S>> v_out) {
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    const S* a = q0.data() + joint.idx_q;
    const S* b = q1.data() + joint.idx_q;
    S* out = v_out.data() + joint.idx_v;
    if (joint.type != JointType::Floating) {
      out[0] = b[0] - a[0];
      continue;
    }
    // Relative rotation dq = conj(qa) qb, taken with w >= 0 (the same rotation, the short way).
    const Eigen::Matrix<S, 4, 1> qa_conj(-a[3], -a[4], -a[5], a[6]);
    Eigen::Matrix<S, 4, 1> dq = detail::quat_multiply<S>(qa_conj, Eigen::Matrix<S, 4, 1>(b[3], b[4], b[5], b[6]));
    dq /= dq.norm();
    if (dq[3] < S(0)) dq = -dq;
    const Vec3<S> xyz(dq[0], dq[1], dq[2]);
    const S s = xyz.norm();
    const S theta = S(2) * atan2(s, dq[3]);
    // w = theta xyz / s, with theta / s -> 2 (1 + s^2 / 6) as s -> 0.
    const S scale = s < S(1e-6) ? S(2) * (S(1) + s * s / S(6)) : theta / s;
    const Vec3<S> w = xyz * scale;
    // lin = V(w)^-1 R_a^T (p_b - p_a), V^-1 = I - [w]/2 + c [w]^2, c = (1 - t sin t / (2 (1 - cos t))) / t^2.
    const Mat3<S> Ra = quaternion_to_rotation<S>(a[3], a[4], a[5], a[6]);
    const Vec3<S> p = Ra.transpose() * Vec3<S>(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    const S c = theta < S(1e-4) ? S(1) / S(12) + theta * theta / S(720)
                                : (S(1) - theta * sin(theta) / (S(2) * (S(1) - cos(theta)))) / (theta * theta);
    const Mat3<S> wx = skew<S>(w);
    const Vec3<S> lin = p - wx * p / S(2) + c * (wx * (wx * p));
    for (int k = 0; k < 3; ++k) {
      out[k] = lin[k];
      out[3 + k] = w[k];
    }
  }
}

/// dq/dt (size nq) for velocity v: the ambient-space derivative used by explicit integrators
/// (position rate R_WB v_lin, quaternion rate 1/2 quat * (w, 0)).
template <typename S>
void configuration_derivative(const Model& model, const Eigen::Ref<const VecX<S>>& q,
                              const Eigen::Ref<const VecX<S>>& v, Eigen::Ref<VecX<S>> qdot) {
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    const S* qj = q.data() + joint.idx_q;
    const S* vj = v.data() + joint.idx_v;
    S* out = qdot.data() + joint.idx_q;
    if (joint.type != JointType::Floating) {
      out[0] = vj[0];
      continue;
    }
    const Eigen::Matrix<S, 4, 1> quat(qj[3], qj[4], qj[5], qj[6]);
    const Mat3<S> R = quaternion_to_rotation<S>(quat[0], quat[1], quat[2], quat[3]);
    const Vec3<S> pdot = R * Vec3<S>(vj[0], vj[1], vj[2]);
    Eigen::Matrix<S, 4, 1> omega(vj[3], vj[4], vj[5], S(0));
    const Eigen::Matrix<S, 4, 1> quat_dot = detail::quat_multiply<S>(quat, omega) / S(2);
    for (int k = 0; k < 3; ++k) out[k] = pdot[k];
    for (int k = 0; k < 4; ++k) out[3 + k] = quat_dot[k];
  }
}

/// Normalises every floating base's quaternion in place.
template <typename S> void normalize_configuration(const Model& model, Eigen::Ref<VecX<S>> q) {
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    if (joint.type == JointType::Floating) q.template segment<4>(joint.idx_q + 3).normalize();
  }
}

}  // namespace mbgen
