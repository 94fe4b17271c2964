#pragma once
// The independent reference of the analytic derivatives (test_rnea_derivatives.cpp, the bench's
// derivative-accuracy study): the generic runtime, templated on its scalar, run on Eigen's
// forward-mode AutoDiffScalar (Debian's libeigen3-dev, unsupported/Eigen/AutoDiff) computes a
// function and one directional derivative exactly, to round-off; one pass per column.
#include <Eigen/Core>
#include <unsupported/Eigen/AutoDiff>

#include "mbgen/mbgen.hpp"

namespace mbgen::test {

using Dual = Eigen::AutoDiffScalar<Eigen::Matrix<double, 1, 1>>;

/// x as duals with zero derivatives, entry k's derivative 1 if k >= 0.
inline VecX<Dual> seeded_vector(const VecX<double>& x, int k = -1) {
  VecX<Dual> out(x.size());
  for (int r = 0; r < x.size(); ++r) out[r] = Dual(x[r], Eigen::Matrix<double, 1, 1>(r == k ? 1.0 : 0.0));
  return out;
}

/// q (+) eps delta to first order in eps (delta in v-space), as a dual configuration: a 1-DoF
/// joint's coordinate plus eps delta; a floating base's position plus R eps delta_lin and its
/// quaternion times (eps delta_ang/2, 1): the first-order terms of `integrate`'s exponential (whose
/// own sqrt of |w|^2 has no derivative at w = 0).
inline VecX<Dual> seeded_configuration_along(const Model& model, const VecX<double>& q, const VecX<double>& delta) {
  VecX<Dual> out = seeded_vector(q);
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    if (joint.type != JointType::Floating) {
      for (int k = 0; k < joint.nv; ++k) out[joint.idx_q + k].derivatives()[0] = delta[joint.idx_v + k];
      continue;
    }
    const double* qj = q.data() + joint.idx_q;
    const Mat3<double> R = quaternion_to_rotation<double>(qj[3], qj[4], qj[5], qj[6]);
    const Vec3<double> linear = R * delta.segment<3>(joint.idx_v);
    for (int r = 0; r < 3; ++r) out[joint.idx_q + r].derivatives()[0] = linear[r];
    Eigen::Matrix<double, 4, 1> half_e = Eigen::Matrix<double, 4, 1>::Zero();
    half_e.head<3>() = 0.5 * delta.segment<3>(joint.idx_v + 3);  // (x, y, z, w) = (e/2, 0): the eps part of (eps e/2, 1)
    const Eigen::Matrix<double, 4, 1> dquat = detail::quat_multiply<double>(Eigen::Matrix<double, 4, 1>(qj[3], qj[4], qj[5], qj[6]), half_e);
    for (int r = 0; r < 4; ++r) out[joint.idx_q + 3 + r].derivatives()[0] = dquat[r];
  }
  return out;
}

/// q (+) eps e_k to first order in eps.
inline VecX<Dual> seeded_configuration(const Model& model, const VecX<double>& q, int k) {
  return seeded_configuration_along(model, q, VecX<double>::Unit(model.nv(), k));
}

inline VecX<double> derivative_part(const VecX<Dual>& x) {
  VecX<double> d(x.size());
  for (int r = 0; r < x.size(); ++r) d[r] = x[r].derivatives()[0];
  return d;
}

/// The dual-number Jacobians of rnea (wrt q, v at (q, v, a)) and aba (wrt q, v, tau at (q, v, tau)).
struct DualJacobians {
  MatX<double> dtau_dq, dtau_dv, dddq_dq, dddq_dv, dddq_dtau;
};
inline DualJacobians dual_jacobians(const Model& model, const VecX<double>& q, const VecX<double>& v, const VecX<double>& a,
                                    const VecX<double>& tau) {
  const int nv = model.nv();
  DualJacobians out{MatX<double>(nv, nv), MatX<double>(nv, nv), MatX<double>(nv, nv), MatX<double>(nv, nv), MatX<double>(nv, nv)};
  Data<Dual> data(model);
  const VecX<Dual> qd = seeded_vector(q), vd = seeded_vector(v), ad = seeded_vector(a), taud = seeded_vector(tau);
  for (int k = 0; k < nv; ++k) {
    const VecX<Dual> qk = seeded_configuration(model, q, k), vk = seeded_vector(v, k), tk = seeded_vector(tau, k);
    out.dtau_dq.col(k) = derivative_part(rnea<Dual>(model, data, qk, vd, ad));
    out.dtau_dv.col(k) = derivative_part(rnea<Dual>(model, data, qd, vk, ad));
    out.dddq_dq.col(k) = derivative_part(aba<Dual>(model, data, qk, vd, taud));
    out.dddq_dv.col(k) = derivative_part(aba<Dual>(model, data, qd, vk, taud));
    out.dddq_dtau.col(k) = derivative_part(aba<Dual>(model, data, qd, vd, tk));
  }
  return out;
}

}  // namespace mbgen::test
