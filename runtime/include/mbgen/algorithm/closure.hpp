#pragma once
// Loop-closure constraints on top of the tree: residual Phi(q), Jacobian Phi_q (velocity
// coordinates) and bias gamma with Phi_q qdd = gamma. Row convention: loop_closure.hpp.
//
// Rows of one closure, with Ca, Cb its two frames, R = R_CaCb, r = p_CaCb (Cb's origin in Ca)
// and (u1, u2, a) the right-handed basis of Ca whose third vector is the closure axis a:
//   weld       [r; vee(R - R^T)/2]
//   point      r
//   revolute   [r; -u2.(R a); u1.(R a)]
//   prismatic  [u1.r; u2.r; vee(R - R^T)/2]
//   universal  [r; -a.(R b)]                    (b = axis_b, fixed in Cb)
//   coupling   q_b - ratio q_a - offset         (q_a, q_b: the positions of the joints moving
//                                                body_a and body_b; linear, so gamma = 0)
// Phi_q has the rows of the relative motion of Cb with respect to Ca, expressed in Ca: the
// linear rows are the exact derivative of Phi everywhere, the angular rows on the closed set
// Phi = 0 (where R a = a, R = I), which is where the dynamics use them; Newton, which may start
// off it, keeps its quadratic convergence (the Jacobian error is O(|Phi|)).
//
// Only the joints strictly below the closure's common ancestor T (its top) enter Phi, Phi_q and
// gamma: those above move Ca and Cb alike. So every row is computed from the cycle alone, in T's
// frame with T taken at rest (cycle_kinematics): the poses and motion of T and of what is above
// it, which would cancel exactly in the world frame, never enter (Lola's knee loop is not
// carried through the floating base and the hip), and the columns of the joints above are exact
// zeros rather than round-off.
#include "mbgen/algorithm/kinematics.hpp"

namespace mbgen {

/// Right-handed orthonormal basis (u1, u2, a) of a closure frame whose third column is the unit
/// axis a. u1 = normalize(e x a), e the coordinate axis least aligned with a (the first such),
/// so the basis is a constant of the model.
inline Mat3<double> closure_axis_basis(const Vec3<double>& axis) {
  const Vec3<double> a = axis.normalized();
  int least = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(a[k]) < std::abs(a[least])) least = k;
  const Vec3<double> u1 = Vec3<double>::Unit(least).cross(a).normalized();
  Mat3<double> B;
  B << u1, a.cross(u1), a;
  return B;
}

namespace detail {

/// vee((R - R^T) / 2): the rotation vector of R to first order.
template <typename S> Vec3<S> rotation_skew_vee(const Mat3<S>& R) {
  return Vec3<S>(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1)) / S(2);
}

/// X_J and X_PB of the bodies on the closures' cycles (ModelStructure::cycle_bodies), the only poses the
/// loops' rows read: cycle_kinematics places a cycle from X_PB alone, its top at rest. Newton on
/// the loops places these rather than the whole tree (Lola: 22 of its 46 bodies, and no world
/// poses).
template <typename S> void cycle_placements(const Model& model, Data<S>& data, const S* q) {
  for (BodyIndex b : model.structure().cycle_bodies) place_in_parent<S>(model, data, q, b);
}

/// Fills data.X_TB (and, with v, data.v_T and data.a_T at zero joint accelerations) for the
/// bodies from top (excluded) down to b, top an ancestor of b or b itself, as if top were at rest.
/// Needs data.X_PB. Recurses to the top first: a cycle is a few bodies.
template <typename S> void cycle_branch(const Model& model, Data<S>& data, BodyIndex top, BodyIndex b, const S* v) {
  if (b == top) return;
  const BodyIndex parent = model.body(b).parent;
  cycle_branch<S>(model, data, top, parent, v);
  const Joint& joint = model.joint(model.body(b).joint);
  const bool below_top = parent != top;
  data.X_TB[b] = below_top ? data.X_TB[parent] * data.X_PB[b] : data.X_PB[b];
  if (!v) return;
  const Motion<S> vj = joint_velocity<S>(joint, v + joint.idx_v);
  if (below_top) {
    data.v_T[b] = data.X_PB[b].act_inv(data.v_T[parent]) + vj;
    data.a_T[b] = data.X_PB[b].act_inv(data.a_T[parent]) + data.v_T[b].cross(vj);
  } else {  // T at rest: v = vj, and vj x vj = 0
    data.v_T[b] = vj;
    data.a_T[b] = Motion<S>::Zero();
  }
}

/// The closure's top T (common ancestor of its bodies) after filling the cycle's data.X_TB (and
/// with v, data.v_T, data.a_T) on both branches. Needs data.X_PB (forward kinematics).
template <typename S> BodyIndex cycle_kinematics(const Model& model, Data<S>& data, const LoopClosure& c, const S* v) {
  const BodyIndex top = closure_top(model, c);
  cycle_branch<S>(model, data, top, c.body_a, v);
  cycle_branch<S>(model, data, top, c.body_b, v);
  return top;
}

/// Quantities of a closure frame fixed in body b at X_BC, relative to the cycle's top T at rest:
/// pose, velocity and classical (non-spatial) acceleration of its origin, angular velocity and
/// acceleration, all in T's axes. Needs cycle_kinematics (with velocities for the rates).
template <typename S> struct FrameState {
  Mat3<S> R;
  Vec3<S> p, v, w, dv, dw;
};

template <typename S>
FrameState<S> closure_frame_state(const Data<S>& data, BodyIndex top, BodyIndex b, const SE3<double>& X_BC, bool with_rates) {
  FrameState<S> f;
  const Vec3<S> r = X_BC.translation.cast<S>();
  if (b == top) {  // a frame on T itself is at rest
    f.R = X_BC.rotation.cast<S>();
    f.p = r;
    f.v = f.w = f.dv = f.dw = Vec3<S>::Zero();
    return f;
  }
  const SE3<S>& X_TB = data.X_TB[b];
  f.R = X_TB.rotation * X_BC.rotation.cast<S>();
  f.p = X_TB.act(r);
  if (!with_rates) return f;
  const Motion<S>& vb = data.v_T[b];
  const Motion<S>& ab = data.a_T[b];
  const Vec3<S> v_point = vb.linear + vb.angular.cross(r);  // body axes
  f.v = X_TB.rotation * v_point;
  f.w = X_TB.rotation * vb.angular;
  // a is the derivative of the body twist's components: the point's classical acceleration
  // adds the transport term w x v_point.
  f.dv = X_TB.rotation * (ab.linear + ab.angular.cross(r) + vb.angular.cross(v_point));
  f.dw = X_TB.rotation * ab.angular;
  return f;
}

/// Residual rows of one closure into out[0 .. rows). Needs cycle_kinematics (top: its result).
template <typename S> void closure_residual_rows(const Data<S>& data, const LoopClosure& c, BodyIndex top, S* out) {
  const FrameState<S> A = closure_frame_state<S>(data, top, c.body_a, c.X_ACa, false);
  const FrameState<S> B = closure_frame_state<S>(data, top, c.body_b, c.X_BCb, false);
  const Mat3<S> R = A.R.transpose() * B.R;
  const Vec3<S> r = A.R.transpose() * (B.p - A.p);
  const Mat3<double> basis = closure_axis_basis(c.axis);
  const Vec3<S> u1 = basis.col(0).cast<S>(), u2 = basis.col(1).cast<S>(), a = basis.col(2).cast<S>();
  switch (c.type) {
    case ClosureType::Weld: {
      const Vec3<S> e = rotation_skew_vee<S>(R);
      for (int k = 0; k < 3; ++k) out[k] = r[k], out[3 + k] = e[k];
      break;
    }
    case ClosureType::Point:
      for (int k = 0; k < 3; ++k) out[k] = r[k];
      break;
    case ClosureType::Revolute: {
      const Vec3<S> Ra = R * a;
      for (int k = 0; k < 3; ++k) out[k] = r[k];
      out[3] = -u2.dot(Ra);
      out[4] = u1.dot(Ra);
      break;
    }
    case ClosureType::Prismatic: {
      const Vec3<S> e = rotation_skew_vee<S>(R);
      out[0] = u1.dot(r);
      out[1] = u2.dot(r);
      for (int k = 0; k < 3; ++k) out[2 + k] = e[k];
      break;
    }
    case ClosureType::Universal:
      for (int k = 0; k < 3; ++k) out[k] = r[k];
      out[3] = -a.dot(R * c.axis_b.cast<S>());
      break;
    case ClosureType::Coupling: break;  // not a relative motion: coupling_residual
  }
}

/// Maps a relative motion of Cb with respect to Ca (in Ca: linear rows of the origin, angular)
/// to the closure's rows. n_u is the universal closure's angular row direction a x (R b).
template <typename S>
void select_closure_rows(const LoopClosure& c, const Mat3<double>& basis, const Vec3<S>& n_u, const Vec3<S>& lin,
                         const Vec3<S>& ang, S* out, int stride) {
  const Vec3<S> u1 = basis.col(0).cast<S>(), u2 = basis.col(1).cast<S>();
  switch (c.type) {
    case ClosureType::Weld:
      for (int k = 0; k < 3; ++k) out[k * stride] = lin[k], out[(3 + k) * stride] = ang[k];
      break;
    case ClosureType::Point:
      for (int k = 0; k < 3; ++k) out[k * stride] = lin[k];
      break;
    case ClosureType::Revolute:
      for (int k = 0; k < 3; ++k) out[k * stride] = lin[k];
      out[3 * stride] = u1.dot(ang);
      out[4 * stride] = u2.dot(ang);
      break;
    case ClosureType::Prismatic:
      out[0] = u1.dot(lin);
      out[stride] = u2.dot(lin);
      for (int k = 0; k < 3; ++k) out[(2 + k) * stride] = ang[k];
      break;
    case ClosureType::Universal:
      for (int k = 0; k < 3; ++k) out[k * stride] = lin[k];
      out[3 * stride] = n_u.dot(ang);
      break;
    case ClosureType::Coupling: break;  // not a relative motion: coupling_jacobian_row
  }
}

/// a x (R b) of a universal closure (zero vector otherwise), R = R_CaCb.
template <typename S> Vec3<S> universal_row_direction(const LoopClosure& c, const Mat3<double>& basis, const Mat3<S>& R) {
  if (c.type != ClosureType::Universal) return Vec3<S>::Zero();
  return basis.col(2).cast<S>().cross(R * c.axis_b.cast<S>());
}

/// Jacobian rows of one closure into the block J (rows x nv). Only the columns of the closure's
/// cycle (the joints between body_a, body_b and their common ancestor) are written; every other
/// column of J must already be zero, as Data::Phi_q is from its construction. Writing just the
/// cycle keeps closure_jacobian O(n) over all closures (each cycle is short), where zeroing m x nv
/// entries would make it O(m nv). Needs cycle_kinematics (top: its result).
template <typename S, typename Block>
void closure_jacobian_rows(const Model& model, const Data<S>& data, const LoopClosure& c, BodyIndex top, Block&& J) {
  for (BodyIndex j : {c.body_a, c.body_b})
    for (; j != top; j = model.body(j).parent) {
      const Joint& joint = model.joint(model.body(j).joint);
      for (int k = 0; k < joint.nv; ++k) J.col(joint.idx_v + k).setZero();
    }
  const FrameState<S> A = closure_frame_state<S>(data, top, c.body_a, c.X_ACa, false);
  const FrameState<S> B = closure_frame_state<S>(data, top, c.body_b, c.X_BCb, false);
  const Mat3<double> basis = closure_axis_basis(c.axis);
  const Vec3<S> n_u = universal_row_direction<S>(c, basis, Mat3<S>(A.R.transpose() * B.R));
  // A column moves Cb's origin (b side, +) or the point of body A coincident with it (a side, -).
  for (int side = 0; side < 2; ++side) {
    const S sign = side == 0 ? S(1) : S(-1);
    for (BodyIndex j = side == 0 ? c.body_b : c.body_a; j != top; j = model.body(j).parent) {
      const Joint& joint = model.joint(model.body(j).joint);
      for (int k = 0; k < joint.nv; ++k) {
        const int col = joint.idx_v + k;
        // The joint's motion in T's axes, its linear part at T's origin.
        const Motion<S> m = data.X_TB[j].act(joint_subspace_column<S>(joint, k));
        const Vec3<S> lin = sign * (A.R.transpose() * (m.linear + m.angular.cross(B.p)));
        const Vec3<S> ang = sign * (A.R.transpose() * m.angular);
        S rows[6];
        select_closure_rows<S>(c, basis, n_u, lin, ang, rows, 1);
        for (int i = 0; i < c.rows(); ++i) J(i, col) += rows[i];
      }
    }
  }
}

/// Rows of d/dt (Phi_q v) at zero joint accelerations into out[0 .. rows). Needs
/// cycle_kinematics with velocities (top: its result).
template <typename S> void closure_velocity_product_rows(const Data<S>& data, const LoopClosure& c, BodyIndex top, S* out) {
  const FrameState<S> A = closure_frame_state<S>(data, top, c.body_a, c.X_ACa, true);
  const FrameState<S> B = closure_frame_state<S>(data, top, c.body_b, c.X_BCb, true);
  const Mat3<S> Rt = A.R.transpose();
  const Vec3<S> d = B.p - A.p, dd = B.v - A.v;
  // c_lin = Ra^T (vb - va - wa x d), c_ang = Ra^T (wb - wa); d/dt Ra^T = -Ra^T [wa]x.
  const Vec3<S> rel_lin = dd - A.w.cross(d), rel_ang = B.w - A.w;
  const Vec3<S> lin = Rt * (B.dv - A.dv - A.dw.cross(d) - A.w.cross(dd) - A.w.cross(rel_lin));
  const Vec3<S> ang = Rt * (B.dw - A.dw - A.w.cross(rel_ang));
  const Mat3<double> basis = closure_axis_basis(c.axis);
  const Mat3<S> R = Rt * B.R;
  const Vec3<S> n_u = universal_row_direction<S>(c, basis, R);
  select_closure_rows<S>(c, basis, n_u, lin, ang, out, 1);
  if (c.type == ClosureType::Universal) {
    // The row direction n = a x (R b) turns with the relative rotation: n' = a x (w_rel x R b).
    const Vec3<S> w_rel = Rt * rel_ang;
    const Vec3<S> n_dot = basis.col(2).cast<S>().cross(w_rel.cross(R * c.axis_b.cast<S>()));
    out[3] += n_dot.dot(w_rel);
  }
}

/// A coupling's row, q_b - ratio q_a - offset: the positions themselves, not the placements
/// (the loaders give couplings 1-DoF joints with one position coordinate each).
template <typename S> S coupling_residual(const Model& model, const LoopClosure& c, const S* q) {
  const int qa = model.joint(model.body(c.body_a).joint).idx_q, qb = model.joint(model.body(c.body_b).joint).idx_q;
  return q[qb] - S(c.ratio) * q[qa] - S(c.offset);
}

/// A coupling's Jacobian row into the 1-row block J: +1 at the follower, -ratio at the leader,
/// the rest of its cycle's columns zero (closure_jacobian_rows' contract).
template <typename S, typename Block> void coupling_jacobian_row(const Model& model, const LoopClosure& c, Block&& J) {
  const BodyIndex top = closure_top(model, c);
  for (BodyIndex j : {c.body_a, c.body_b})
    for (; j != top; j = model.body(j).parent) {
      const Joint& joint = model.joint(model.body(j).joint);
      for (int k = 0; k < joint.nv; ++k) J(0, joint.idx_v + k) = S(0);
    }
  J(0, model.joint(model.body(c.body_b).joint).idx_v) = S(1);
  J(0, model.joint(model.body(c.body_a).joint).idx_v) = S(-c.ratio);
}

// The stacked rows of every closure from the joints' placements X_PB of the cycles' bodies
// (forward kinematics places them with the rest of the tree, cycle_placements alone): the public
// functions below run the former, Newton and the sub-systems' maps the latter.

/// The residual into data.Phi (q: the positions the placements are of, for the couplings).
template <typename S> void residual_from_placements(const Model& model, Data<S>& data, const S* q) {
  for (const LoopClosure& c : model.closures) {
    if (c.type == ClosureType::Coupling) {
      data.Phi[c.row_offset] = coupling_residual<S>(model, c, q);
      continue;
    }
    const BodyIndex top = cycle_kinematics<S>(model, data, c, nullptr);
    closure_residual_rows<S>(data, c, top, data.Phi.data() + c.row_offset);
  }
}

/// The constraint Jacobian into data.Phi_q.
template <typename S> void jacobian_from_placements(const Model& model, Data<S>& data) {
  for (const LoopClosure& c : model.closures) {
    if (c.type == ClosureType::Coupling) {
      coupling_jacobian_row<S>(model, c, data.Phi_q.middleRows(c.row_offset, 1));
      continue;
    }
    const BodyIndex top = cycle_kinematics<S>(model, data, c, nullptr);
    closure_jacobian_rows<S>(model, data, c, top, data.Phi_q.middleRows(c.row_offset, c.rows()));
  }
}

/// The bias into data.gamma, for velocities v (nv).
template <typename S> void bias_from_placements(const Model& model, Data<S>& data, const S* v) {
  for (const LoopClosure& c : model.closures) {
    if (c.type == ClosureType::Coupling) {  // Phi_q is constant
      data.gamma[c.row_offset] = S(0);
      continue;
    }
    const BodyIndex top = cycle_kinematics<S>(model, data, c, v);
    S* out = data.gamma.data() + c.row_offset;
    closure_velocity_product_rows<S>(data, c, top, out);
    for (int i = 0; i < c.rows(); ++i) out[i] = -out[i];
  }
}

}  // namespace detail

/// Stacked residual Phi(q) of all closures (model.num_constraint_rows()) in data.Phi, also
/// returned. Runs forward kinematics for q (size nq).
template <typename S> const VecX<S>& closure_residual(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  forward_kinematics<S>(model, data, q);
  detail::residual_from_placements<S>(model, data, q.data());
  return data.Phi;
}

/// Constraint Jacobian Phi_q (m x nv, velocity coordinates: Phi_q v is the stacked relative
/// velocity of the closures) in data.Phi_q, also returned. Runs forward kinematics for q.
template <typename S> const MatX<S>& closure_jacobian(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  forward_kinematics<S>(model, data, q);
  detail::jacobian_from_placements<S>(model, data);
  return data.Phi_q;
}

/// Bias gamma (m) with Phi_q qdd = gamma on a motion that keeps the loops closed:
/// gamma = -(d/dt Phi_q) v, from the cycles' accelerations at qdd = 0. In data.gamma, also
/// returned. Runs forward kinematics for q.
template <typename S>
const VecX<S>& closure_bias(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  forward_kinematics<S>(model, data, q);
  detail::bias_from_placements<S>(model, data, v.data());
  return data.gamma;
}

/// Residual, Jacobian and bias in one pass of the kinematics (data.Phi, data.Phi_q, data.gamma as
/// the three functions above write them): the loops in full coordinates, as a solver that keeps
/// them by multipliers reads them (the simulator's soft span through a dead point).
template <typename S>
void closure_constraints(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  forward_kinematics<S>(model, data, q);
  detail::residual_from_placements<S>(model, data, q.data());
  detail::jacobian_from_placements<S>(model, data);
  detail::bias_from_placements<S>(model, data, v.data());
}

/// How many closure rows the sub-systems keep (SubSystem::rows, the rank of each): the rows of
/// closure_constraints a full-coordinate solver needs, independent at the assembled pose.
inline int num_kept_closure_rows(const Model& model) {
  int n = 0;
  for (const SubSystem& s : model.subsystems) n += s.rank();
  return n;
}

}  // namespace mbgen
