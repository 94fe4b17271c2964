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
// df/dw and df/dv_w are the law's 3 x 3 Jacobians (contact_force_jacobians, contact_law.hpp).
// The ground's part joins the inverse dynamics' before the solves with M:
//   da/dq = -M^-1 (dtau/dq - dtau_c/dq), and the same along v,
// so the generator traces up to those solves and prints them as loops (as the tree's, aba_derivatives.hpp).
#include <vector>

#include <Eigen/Core>

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
        dtau_dv(MatX<S>::Zero(model.nv(), model.nv())),
        dF_q(fd.J.size()),
        dF_v(fd.J.size()) {}

  /// Results in fd: fd.ddq = a, fd.dddq_dq = da/dq, fd.dddq_dv = da/dv, fd.Minv = da/dtau (nv x nv,
  /// Eigen's column-major storage); fd.tau, fd.dtau_dq, fd.dtau_dv: the inverse dynamics' at a
  /// without the ground.
  DynamicsDerivatives<S> fd;
  VecX<S> tau_total;         ///< tau + tau_c at the last call
  MatX<S> dtau_dq, dtau_dv;  ///< the ground's joint forces' derivatives, dtau_c/dq and dtau_c/dv
  std::vector<Force<S>> dF_q, dF_v;  ///< work: per sweep column, a body's spheres' summed dF along q and v
};

namespace detail {
/// dtau_c/dq and dtau_c/dv (d.dtau_dq, d.dtau_dv; header comment) from the sweep's columns and
/// twists and the bodies' poses (d.fd, filled at the same q and v; in its axes). The spheres on one
/// body (consecutive, as contact_spheres lists them) share its chain: their dF per column add up
/// first and their wrenches into one, and the chain's columns project the sums once, which is
/// most of the work (a flat foot's four to six spheres: that many times less).
template <typename S>
void contact_joint_force_derivatives(const std::vector<ContactSphere>& spheres,
                                     double exponent, const S* ground, const S* law, ContactDynamicsDerivatives<S>& d) {
  const auto at = [](int k) { return static_cast<std::size_t>(k); };
  const DynamicsDerivatives<S>& id = d.fd;
  d.dtau_dq.setZero();
  d.dtau_dv.setZero();
  // The ground in the sweep's axes (the root's; id.X[world] the world's pose in them), where the
  // spheres' centres and twists are: the normal turned, the offset moved with the origin
  // (with [Q | t] = X[world], c_world = Q^T (c - t) and n = Q n_world, so
  // offset - n_world . c_world = offset + n . t - n . c).
  const SE3<S>& world = id.X[kWorldBody];
  const Vec3<S> n = world.rotation * Vec3<S>(ground[0], ground[1], ground[2]);
  const S ground_in_axes[4] = {n[0], n[1], n[2], ground[3] + n.dot(world.translation)};
  std::size_t k = 0;
  while (k < spheres.size()) {
    const int b = spheres[k].body.value();
    const Motion<S>& V = id.V[at(b)];
    for (int j = b; j != 0; j = id.bodies[at(j)].parent)
      for (int s = id.bodies[at(j)].first_column; s < id.bodies[at(j)].first_column + id.bodies[at(j)].num_columns; ++s)
        d.dF_q[at(s)] = d.dF_v[at(s)] = Force<S>::Zero();
    Force<S> F_body = Force<S>::Zero();
    for (; k < spheres.size() && spheres[k].body.value() == b; ++k) {
      const Vec3<S> c = id.X[spheres[k].body].act(cast<S>(spheres[k].center));
      const Vec3<S> w = c - S(spheres[k].radius) * n;
      // No test for contact: apart, the law's force and Jacobians are exactly 0, and the traced
      // form (the generated contact_forward_dynamics_derivatives) cannot branch on the state.
      Vec3<S> f;
      Mat3<S> df_dw, df_dv;
      contact_force_jacobians<S>(w, V.linear + V.angular.cross(w), ground_in_axes, law, exponent, f, df_dw, df_dv);
      F_body += Force<S>{f, w.cross(f)};
      // Column s of the chain: along q and along v.
      for (int j = b; j != 0; j = id.bodies[at(j)].parent) {
        const auto& sj = id.bodies[at(j)];
        const Motion<S>& Vp = id.V[at(sj.parent)];
        for (int s = sj.first_column; s < sj.first_column + sj.num_columns; ++s) {
          const Motion<S>& col = id.J[at(s)];
          const Vec3<S> dw = col.linear + col.angular.cross(c);
          const Motion<S> dV = col.cross(V - Vp);
          const Vec3<S> df_q = df_dw * dw + df_dv * (dV.linear + dV.angular.cross(w) + V.angular.cross(dw));
          d.dF_q[at(s)] += Force<S>{df_q, dw.cross(f) + w.cross(df_q)};
          const Vec3<S> df_v = df_dv * (col.linear + col.angular.cross(w));
          d.dF_v[at(s)] += Force<S>{df_v, w.cross(df_v)};
        }
      }
    }
    // The sums projected on the chain's columns; the columns at or below j turn with it.
    for (int j = b; j != 0; j = id.bodies[at(j)].parent) {
      const auto& sj = id.bodies[at(j)];
      for (int s = sj.first_column; s < sj.first_column + sj.num_columns; ++s) {
        const int sv = id.column_v[at(s)];
        const Force<S> turned = id.J[at(s)].cross(F_body);
        bool below = true;  // i's body at or below j
        for (int i = b; i != 0; i = id.bodies[at(i)].parent) {
          const auto& si = id.bodies[at(i)];
          for (int c = si.first_column; c < si.first_column + si.num_columns; ++c) {
            const int iv = id.column_v[at(c)];
            d.dtau_dq(iv, sv) += id.J[at(c)].dot(d.dF_q[at(s)]) - (below ? id.J[at(c)].dot(turned) : S(0));
            d.dtau_dv(iv, sv) += id.J[at(c)].dot(d.dF_v[at(s)]);
          }
          if (i == j) below = false;
        }
      }
    }
  }
}
}  // namespace detail

/// What comes before the solves with M (the part the generator unrolls, as
/// forward_dynamics_derivatives_before_solves): d.fd.ddq = a, d.fd.dddq_dq = dtau_c/dq - dtau/dq and
/// d.fd.dddq_dv = dtau_c/dv - dtau/dv (dtau the inverse dynamics' at (q, v, a) without the ground),
/// d.fd.Minv = M^-1 and M's factor; out as contact_forward_dynamics writes it. No allocation.
template <typename S>
void contact_forward_dynamics_derivatives_before_solves(const Model& model, Data<S>& data, ContactDynamicsDerivatives<S>& d,
                                                        const std::vector<ContactSphere>& spheres, double exponent,
                                                        const ConstVecRef<S>& q, const ConstVecRef<S>& v, const ConstVecRef<S>& tau,
                                                        const S* ground, const S* law, S* out) {
  d.tau_total = tau;
  contact_joint_forces<S>(model, data, spheres, exponent, q, v.data(), ground, law, d.tau_total.data(), out);
  forward_dynamics_derivatives_before_solves<S>(model, data, d.fd, q, v, d.tau_total);
  if (spheres.empty()) return;
  detail::contact_joint_force_derivatives<S>(spheres, exponent, ground, law, d);
  // -M^-1 (dtau - dtau_c): the ground's part joins before the solves, one solve for both.
  d.fd.dddq_dq += d.dtau_dq;
  d.fd.dddq_dv += d.dtau_dv;
}

/// a (d.fd.ddq) at (q, v, tau) under the ground's forces on the spheres, and da/dq, da/dv, da/dtau
/// (header comment; results listed in ContactDynamicsDerivatives). ground and law as
/// contact_inputs writes them, exponent the law's; out gets kContactOutputs numbers per sphere, as
/// contact_forward_dynamics writes them. Trees only. No allocation.
template <typename S>
void contact_forward_dynamics_derivatives(const Model& model, Data<S>& data, ContactDynamicsDerivatives<S>& d,
                                          const std::vector<ContactSphere>& spheres, double exponent, const ConstVecRef<S>& q,
                                          const ConstVecRef<S>& v, const ConstVecRef<S>& tau, const S* ground, const S* law,
                                          S* out) {
  contact_forward_dynamics_derivatives_before_solves<S>(model, data, d, spheres, exponent, q, v, tau, ground, law, out);
  forward_dynamics_derivatives_solves<S>(model, data, d.fd);
}

}  // namespace mbgen
