#pragma once
// Derivatives of the forward dynamics with rigid contacts held (rigid_contact_dynamics.hpp): of
// the accelerations a and the contact forces lambda with respect to q, v and tau (what
// Pinocchio's computeConstraintDynamicsDerivatives gives; the same tangent convention for q as
// rnea_derivatives.hpp: q (+) delta, delta in v-space).
//
// At the solution the two residuals vanish:
//   r1(q, v, a, lambda) = ID(q, v, a; external forces lambda) - tau = M a + h - J^T lambda - tau,
//   r2(q, v, a)         = the contacts' accelerations = J a + gamma.
// Differentiating at fixed tau,
//   [M  -J^T] [da     ]     [dr1]
//   [J    0 ] [dlambda] = - [dr2],     dr1, dr2 the partial derivatives at fixed a and lambda,
// so with P = M^-1 dr1 and Y = M^-1 J^T:  dlambda = (J Y)^-1 (J P - dr2),  da = -P + Y dlambda;
// and along tau (dr1 = -dtau): dlambda/dtau = -(J Y)^-1 Y^T, da/dtau = M^-1 - Y (J Y)^-1 Y^T.
// Computed as: -P by the nv-column solves with M's factor, then dlambda = -(J Y)^-1 (dr2 + J (-P))
// and da = (-P) + Y dlambda; along tau dlambda = -(J Y)^-1 Y^T and da = M^-1 + Y dlambda. The
// generator traces everything before the solves (rigid_contact_derivatives_before_solves: J, Y,
// the factor of J Y, dr1, dr2, M^-1) and prints the solves, those with J Y's factor too, and the
// products as loops (emit_derivatives.hpp), as for the tree's: traced, the solves with J Y's
// factor were two fifths of the function's operations on talos_reduced. (An explicit inverse of
// J Y instead of its solves lost a digit: 2.5e-8 against 1.8e-9 on cassie_like, whose J Y has a
// condition number of 8e5.)
//
// dr1 is the inverse dynamics' derivative (rnea_derivatives.hpp) less that of J^T lambda with
// lambda held fixed in the contact frames' axes. The column J_c (world axes, at the origin) of a
// joint on the chain of the contact's body and that body's wrench F (world axes, at the origin)
// both turn with a column s of a joint at or above c's body, and J_c . F does not change
// ((s x J_c) . F + J_c . (s x* F) = 0); a column s strictly below c's body turns F alone:
//   d(J^T lambda)_c / ds = J_c . (s x* F)   (c's body a strict ancestor of s's), 0 otherwise.
// dr2 comes from the sweep's own world
// velocities V and accelerations A (world axes, at the origin): the column s of a joint on body j
// moves j's subtree rigidly, with j's parent's V_p and A_p unchanged, so for a body i below j
//   along q:  dV_i = s x (V_i - V_p),  dA_i = s x (A_i - A_p - V_p x (V_i - V_p)) + V_p x dV_i,
//             and the contact's point and axes turn with s;
//   along v:  dV_i = s,  dA_i = s x (V_i - V_j - V_p),  the point and axes unchanged,
// and the classical acceleration of the point p, a_p = A_lin + A_ang x p + w x (V_lin + w x p),
// changes by the product rule (contact_acceleration_change below).
#include <vector>

#include "mbgen/algorithm/aba_derivatives.hpp"
#include "mbgen/algorithm/rigid_contact_dynamics.hpp"
#include "mbgen/algorithm/rnea_derivatives.hpp"

namespace mbgen {

/// Results and work memory of rigid_contact_dynamics_derivatives. Making it allocates; the
/// algorithm then does not.
template <typename S> struct RigidContactDerivatives {
  RigidContactDerivatives(const Model& model, const RigidContactWorkspace<S>& ws);

  // Results (Eigen's column-major storage).
  MatX<S> da_dq, da_dv, da_dtau;                ///< nv x nv
  MatX<S> dlambda_dq, dlambda_dv, dlambda_dtau; ///< m x nv

  // Work.
  DynamicsDerivatives<S> id;        ///< the inverse dynamics' derivatives at (q, v, a); M^-1 and M's factor tables
  Force<S> wrench;                  ///< one contact's forces on its body (world axes, at the origin)
  MatX<S> dr1_dq;                   ///< nv x nv: d(ID - J^T lambda)/dq
  MatX<S> dr2_dq, dr2_dv;           ///< m x nv: the contacts' accelerations' partial derivatives
};

template <typename S>
RigidContactDerivatives<S>::RigidContactDerivatives(const Model& model, const RigidContactWorkspace<S>& ws) : id(model) {
  const int nv = model.nv(), m = ws.m;
  for (MatX<S>* x : {&da_dq, &da_dv, &da_dtau, &dr1_dq}) *x = MatX<S>::Zero(nv, nv);
  for (MatX<S>* x : {&dlambda_dq, &dlambda_dv, &dlambda_dtau, &dr2_dq, &dr2_dv}) *x = MatX<S>::Zero(m, nv);
}

namespace detail {
/// The change of the classical acceleration a_p = A_lin + A_ang x p + w x v_p (v_p = V_lin + w x p,
/// w = V_ang) of a point p of a body moving with V and A when they change by dV, dA and p by dp.
template <typename S>
Vec3<S> contact_acceleration_change(const Motion<S>& V, const Motion<S>& A, const Vec3<S>& p, const Motion<S>& dV,
                                    const Motion<S>& dA, const Vec3<S>& dp) {
  const Vec3<S> v_p = V.linear + V.angular.cross(p);
  const Vec3<S> dv_p = dV.linear + dV.angular.cross(p) + V.angular.cross(dp);
  return dA.linear + dA.angular.cross(p) + A.angular.cross(dp) + dV.angular.cross(v_p) + V.angular.cross(dv_p);
}

/// dr2/dq and dr2/dv (d.dr2_dq, d.dr2_dv) from the sweep's V, A and columns (d.id, filled by
/// inverse_dynamics_derivatives at the solution) and the frames' poses data.X_WF, turned into the
/// sweep's axes.
template <typename S>
void rigid_contact_acceleration_derivatives(const Model& model, const Data<S>& data, const RigidContactWorkspace<S>& ws,
                                            RigidContactDerivatives<S>& d) {
  const auto at = [](int k) { return static_cast<std::size_t>(k); };
  const DynamicsDerivatives<S>& id = d.id;
  d.dr2_dq.setZero();
  d.dr2_dv.setZero();
  for (std::size_t k = 0; k < ws.contacts.size(); ++k) {
    const RigidContact& c = ws.contacts[k];
    const int b = model.frame(c.frame).body.value(), r0 = ws.first_row[k];
    const SE3<S> X_F = id.X[kWorldBody] * data.X_WF[c.frame];
    const Mat3<S>& R = X_F.rotation;
    const Vec3<S>& p = X_F.translation;
    const Motion<S>& V = id.V[at(b)];
    const Motion<S> A = id.A[at(b)] - id.A[0];  // the sweep's accelerations carry -gravity
    const Vec3<S> a_p = A.linear + A.angular.cross(p) + V.angular.cross(V.linear + V.angular.cross(p));
    for (int j = b; j != 0; j = id.bodies[at(j)].parent) {
      const auto& sj = id.bodies[at(j)];
      const Motion<S>& Vp = id.V[at(sj.parent)];
      const Motion<S>& Ap = id.A[at(sj.parent)];
      for (int col = sj.first_column; col < sj.first_column + sj.num_columns; ++col) {
        const Motion<S>& s = id.J[at(col)];
        const int iv = id.column_v[at(col)];
        // Along q: the subtree of j, the point and the axes move with s.
        const Motion<S> relative = V - Vp;
        const Motion<S> dVq = s.cross(relative);
        const Motion<S> dAq = s.cross(id.A[at(b)] - Ap - Vp.cross(relative)) + Vp.cross(dVq);
        const Vec3<S> dp = s.linear + s.angular.cross(p);
        const Vec3<S> da_q = contact_acceleration_change<S>(V, A, p, dVq, dAq, dp);
        d.dr2_dq.col(iv).template segment<3>(r0) = R.transpose() * (da_q - s.angular.cross(a_p));
        // Along v: every body below j gains s.
        const Motion<S> dAv = s.cross(V - id.V[at(j)] - Vp);
        const Vec3<S> da_v = contact_acceleration_change<S>(V, A, p, s, dAv, Vec3<S>::Zero());
        d.dr2_dv.col(iv).template segment<3>(r0) = R.transpose() * da_v;
        if (c.rows() == 6) {
          d.dr2_dq.col(iv).template segment<3>(r0 + 3) = R.transpose() * (dAq.angular - s.angular.cross(A.angular));
          d.dr2_dv.col(iv).template segment<3>(r0 + 3) = R.transpose() * dAv.angular;
        }
      }
    }
  }
}

/// dr1/dq = dtau/dq - d(J^T lambda)/dq (d.dr1_dq; header comment) from d.id's columns.
template <typename S>
void rigid_contact_force_derivatives(const Model& model, const Data<S>& data, const RigidContactWorkspace<S>& ws,
                                     RigidContactDerivatives<S>& d) {
  const auto at = [](int k) { return static_cast<std::size_t>(k); };
  const DynamicsDerivatives<S>& id = d.id;
  d.dr1_dq = id.dtau_dq;
  for (std::size_t k = 0; k < ws.contacts.size(); ++k) {
    const RigidContact& c = ws.contacts[k];
    Force<S> local{ws.lambda.template segment<3>(ws.first_row[k]), Vec3<S>::Zero()};
    if (c.rows() == 6) local.angular = ws.lambda.template segment<3>(ws.first_row[k] + 3);
    d.wrench = (id.X[kWorldBody] * data.X_WF[c.frame]).act(local);  // in the sweep's axes
    for (int j = model.frame(c.frame).body.value(); j != 0; j = id.bodies[at(j)].parent) {
      const auto& sj = id.bodies[at(j)];
      for (int s = sj.first_column; s < sj.first_column + sj.num_columns; ++s) {
        const Force<S> turned = id.J[at(s)].cross(d.wrench);
        for (int i = sj.parent; i != 0; i = id.bodies[at(i)].parent) {
          const auto& si = id.bodies[at(i)];
          for (int col = si.first_column; col < si.first_column + si.num_columns; ++col)
            d.dr1_dq(id.column_v[at(col)], id.column_v[at(s)]) -= id.J[at(col)].dot(turned);
        }
      }
    }
  }
}

/// X = -(J Y)^-1 X in place, column by column, from ws.JY_factor.
template <typename S> void negated_contact_operator_solve(const RigidContactWorkspace<S>& ws, MatX<S>& X) {
  for (int c = 0; c < X.cols(); ++c) ldlt_solve<S>(ws.JY_factor, ws.m, X.col(c).data());
  X = -X;
}
}  // namespace detail

/// What comes before the solves with M (the part the generator unrolls): ws.a and ws.lambda (no
/// status: rigid_contact_solve), d.id the inverse dynamics' derivatives at the solution with M's
/// factor tables and M^-1 (forward_dynamics_derivatives' own), and the blocks
/// rigid_contact_derivatives_solves finishes: d.da_dq = -dr1/dq and d.da_dv = -dr1/dv (to be solved
/// into -P), d.dlambda_dq = dr2/dq and d.dlambda_dv = dr2/dv, d.dlambda_dtau = Y^T and d.da_dtau =
/// M^-1. No allocation.
template <typename S>
void rigid_contact_derivatives_before_solves(const Model& model, Data<S>& data, RigidContactWorkspace<S>& ws,
                                             RigidContactDerivatives<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                                             const ConstVecRef<S>& tau) {
  detail::rigid_contact_solve<S>(model, data, ws, q, v, tau);
  inverse_dynamics_derivatives<S>(model, data, d.id, q, v, ws.a);
  detail::mass_matrix_factor_tables<S>(model, data.M, d.id);
  detail::rigid_contact_force_derivatives<S>(model, data, ws, d);
  detail::rigid_contact_acceleration_derivatives<S>(model, data, ws, d);
  d.da_dq = -d.dr1_dq;
  d.da_dv = -d.id.dtau_dv;
  d.dlambda_dq = d.dr2_dq;
  d.dlambda_dv = d.dr2_dv;
  d.dlambda_dtau = ws.Y.transpose();
  d.da_dtau = d.id.Minv;
}

/// The rest: -P = M^-1 (-dr1) in place, dlambda = -(J Y)^-1 (dr2 + J (-P)) and da = (-P) + Y dlambda;
/// along tau dlambda = -(J Y)^-1 Y^T and da = M^-1 + Y dlambda. No allocation.
template <typename S>
void rigid_contact_derivatives_solves(const Model& model, const Data<S>& data, const RigidContactWorkspace<S>& ws,
                                      RigidContactDerivatives<S>& d) {
  for (int c = 0; c < model.nv(); ++c) {
    detail::factor_solve<S>(model, data.M, d.id.inverse_pivot, d.da_dq.col(c));
    detail::factor_solve<S>(model, data.M, d.id.inverse_pivot, d.da_dv.col(c));
  }
  for (auto [da, dlambda] : {std::pair{&d.da_dq, &d.dlambda_dq}, std::pair{&d.da_dv, &d.dlambda_dv}}) {
    dlambda->noalias() += ws.J * *da;
    detail::negated_contact_operator_solve<S>(ws, *dlambda);
    da->noalias() += ws.Y * *dlambda;
  }
  detail::negated_contact_operator_solve<S>(ws, d.dlambda_dtau);
  d.da_dtau.noalias() += ws.Y * d.dlambda_dtau;
}

/// a and lambda (ws.a, ws.lambda, ws.status as rigid_contact_dynamics) and their derivatives with
/// respect to q (along q (+) delta), v and tau (d.da_dq, ..., d.dlambda_dtau) at (q, v, tau).
/// d.id holds the inverse dynamics' derivatives at the solution with the contact forces applied.
/// No allocation.
template <typename S>
void rigid_contact_dynamics_derivatives(const Model& model, Data<S>& data, RigidContactWorkspace<S>& ws,
                                        RigidContactDerivatives<S>& d, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                                        const ConstVecRef<S>& tau) {
  rigid_contact_derivatives_before_solves<S>(model, data, ws, d, q, v, tau);
  rigid_contact_derivatives_solves<S>(model, data, ws, d);
  ws.status = detail::rigid_contact_status<S>(ws);
}

}  // namespace mbgen
