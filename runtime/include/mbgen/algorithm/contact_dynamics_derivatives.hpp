#pragma once
// Derivatives of the forward dynamics under the ground's compliant contacts (contact_dynamics.hpp):
// a = FD(q, v, tau + tau_c(q, v)), tau_c = sum over the spheres of J_w^T f, f the law
// (contact_law.hpp) at the sphere's witness w = c - r n moving with v_w = J_w v. Hence
//   da/dq = dFD/dq + M^-1 dtau_c/dq,  da/dv = dFD/dv + M^-1 dtau_c/dv,  da/dtau = M^-1,
// with dFD the tree's analytic derivatives (aba_derivatives.hpp) taken at tau + tau_c, and the
// same tangent convention for q (q (+) delta, rnea_derivatives.hpp). Trees only (the model's loops
// are refused by the step derivatives, sim/step_derivatives.hpp, which call this).
//
// dtau_c, per sphere on body b, from world quantities (axes and moments at the world origin): the
// body's twist V, the columns S_j of the joints on b's chain, the wrench F = [f; w x f]. The
// column s of a joint on body j of the chain (parent twist V_p) moves j's subtree rigidly:
//   dc = s_lin + s_ang x c = dw   (the witness follows the centre: n and r do not turn),
//   dV = s x (V - V_p),  dv_w = dV_lin + dV_ang x w + V_ang x dw,
//   df = (df/dw) dw + (df/dv_w) dv_w,  dF = [df; dw x f + w x df],
// and the columns at or below j turn with it (dS = s x S), so with (s x S).F = -S.(s x* F)
//   dtau_c,i / ds = S_i . dF - [i at or below j] S_i . (s x* F).
// Along v the point and the columns stay: dv_w = s_lin + s_ang x w and dF = [df; w x df].
// df/dw and df/dv_w are the law's 3 x 3 Jacobians in forward-mode automatic differentiation
// (Eigen's AutoDiffScalar over six inputs: the law is a dozen lines, branch-free but for max).
#include <vector>

#include <Eigen/Core>
#include <unsupported/Eigen/AutoDiff>

#include "mbgen/algorithm/aba_derivatives.hpp"
#include "mbgen/algorithm/contact_points.hpp"

namespace mbgen {

/// Results and work memory of contact_forward_dynamics_derivatives. Making it allocates; the
/// algorithm then does not.
template <typename S> struct ContactDynamicsDerivatives {
  explicit ContactDynamicsDerivatives(const Model& model)
      : fd(model),
        tau_total(VecX<S>::Zero(model.nv())),
        dtau_dq(MatX<S>::Zero(model.nv(), model.nv())),
        dtau_dv(MatX<S>::Zero(model.nv(), model.nv())) {}

  /// Results in fd: fd.ddq = a, fd.dddq_dq = da/dq, fd.dddq_dv = da/dv, fd.Minv = da/dtau (nv x nv,
  /// Eigen's column-major storage); fd.tau, fd.dtau_dq, fd.dtau_dv: the inverse dynamics' at a
  /// without the ground.
  DynamicsDerivatives<S> fd;
  VecX<S> tau_total;         ///< tau + tau_c at the last call
  MatX<S> dtau_dq, dtau_dv;  ///< the ground's joint forces' derivatives, dtau_c/dq and dtau_c/dv
};

namespace detail {
/// The law's Jacobians at a witness w moving at v_w: df/dw and df/dv_w (world axes), and f.
template <typename S>
void contact_law_jacobians(const Vec3<S>& w, const Vec3<S>& v_w, const S* ground, const S* law, double exponent, Vec3<S>& f,
                           Mat3<S>& df_dw, Mat3<S>& df_dv) {
  using AD = Eigen::AutoDiffScalar<Eigen::Matrix<S, 6, 1>>;
  Vec3<AD> w_ad, v_ad;
  for (int i = 0; i < 3; ++i) {
    w_ad[i] = AD(w[i], 6, i);
    v_ad[i] = AD(v_w[i], 6, 3 + i);
  }
  const AD g[kGroundInputs] = {AD(ground[0]), AD(ground[1]), AD(ground[2]), AD(ground[3])};
  const AD l[kLawInputs] = {AD(law[0]), AD(law[1]), AD(law[2]), AD(law[3])};
  const ContactForce<AD> out = contact_force_at_witness<AD>(w_ad, v_ad, g, l, exponent);
  for (int i = 0; i < 3; ++i) {
    f[i] = out.force[i].value();
    // A force that is exactly zero (apart) has an empty derivative vector.
    if (out.force[i].derivatives().size() != 6) {
      df_dw.row(i).setZero();
      df_dv.row(i).setZero();
      continue;
    }
    df_dw.row(i) = out.force[i].derivatives().template head<3>().transpose();
    df_dv.row(i) = out.force[i].derivatives().template tail<3>().transpose();
  }
}

/// dtau_c/dq and dtau_c/dv (d.dtau_dq, d.dtau_dv; header comment) from the sweep's columns and
/// twists (d.fd, filled at the same q and v) and the world poses data.X_WB.
template <typename S>
void contact_joint_force_derivatives(const Data<S>& data, const std::vector<ContactSphere>& spheres,
                                     double exponent, const S* ground, const S* law, ContactDynamicsDerivatives<S>& d) {
  const auto at = [](int k) { return static_cast<std::size_t>(k); };
  const DynamicsDerivatives<S>& id = d.fd;
  d.dtau_dq.setZero();
  d.dtau_dv.setZero();
  const Vec3<S> n(ground[0], ground[1], ground[2]);
  for (const ContactSphere& sphere : spheres) {
    const int b = sphere.body.value();
    const Vec3<S> c = data.X_WB[sphere.body].act(cast<S>(sphere.center));
    const Vec3<S> w = c - S(sphere.radius) * n;
    // Apart, the force is zero in a neighbourhood (and the law's root has no derivative at 0).
    if (!(ground[3] - n.dot(w) > S(0))) continue;
    const Motion<S>& V = id.V[at(b)];
    Vec3<S> f;
    Mat3<S> df_dw, df_dv;
    contact_law_jacobians<S>(w, V.linear + V.angular.cross(w), ground, law, exponent, f, df_dw, df_dv);
    const Force<S> F{f, w.cross(f)};
    // Column s of the chain: along q and along v.
    for (int j = b; j != 0; j = id.bodies[at(j)].parent) {
      const auto& sj = id.bodies[at(j)];
      const Motion<S>& Vp = id.V[at(sj.parent)];
      for (int s = sj.first_column; s < sj.first_column + sj.num_columns; ++s) {
        const Motion<S>& col = id.J[at(s)];
        const int sv = id.column_v[at(s)];
        const Vec3<S> dw = col.linear + col.angular.cross(c);
        const Motion<S> dV = col.cross(V - Vp);
        const Vec3<S> df_q = df_dw * dw + df_dv * (dV.linear + dV.angular.cross(w) + V.angular.cross(dw));
        const Force<S> dF_q{df_q, dw.cross(f) + w.cross(df_q)};
        const Force<S> turned = col.cross(F);
        const Vec3<S> df_v = df_dv * (col.linear + col.angular.cross(w));
        const Force<S> dF_v{df_v, w.cross(df_v)};
        bool below = true;  // i's body at or below j
        for (int i = b; i != 0; i = id.bodies[at(i)].parent) {
          const auto& si = id.bodies[at(i)];
          for (int k = si.first_column; k < si.first_column + si.num_columns; ++k) {
            const int iv = id.column_v[at(k)];
            d.dtau_dq(iv, sv) += id.J[at(k)].dot(dF_q) - (below ? id.J[at(k)].dot(turned) : S(0));
            d.dtau_dv(iv, sv) += id.J[at(k)].dot(dF_v);
          }
          if (i == j) below = false;
        }
      }
    }
  }
}
}  // namespace detail

/// a (d.fd.ddq) at (q, v, tau) under the ground's forces on the spheres, and da/dq, da/dv, da/dtau
/// (header comment; results listed in ContactDynamicsDerivatives). ground and law as
/// contact_inputs writes them, exponent the law's; out gets kContactOutputs numbers per sphere, as
/// contact_forward_dynamics writes them. Trees only. No allocation.
template <typename S>
void contact_forward_dynamics_derivatives(const Model& model, Data<S>& data, ContactDynamicsDerivatives<S>& d,
                                          const std::vector<ContactSphere>& spheres, double exponent, const ConstVecRef<S>& q,
                                          const ConstVecRef<S>& v, const ConstVecRef<S>& tau, const S* ground, const S* law,
                                          S* out) {
  d.tau_total = tau;
  contact_joint_forces<S>(model, data, spheres, exponent, q, v.data(), ground, law, d.tau_total.data(), out);
  forward_dynamics_derivatives<S>(model, data, d.fd, q, v, d.tau_total);
  if (spheres.empty()) return;
  detail::contact_joint_force_derivatives<S>(data, spheres, exponent, ground, law, d);
  d.fd.dddq_dq.noalias() += d.fd.Minv * d.dtau_dq;
  d.fd.dddq_dv.noalias() += d.fd.Minv * d.dtau_dv;
}

}  // namespace mbgen
