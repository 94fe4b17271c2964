#pragma once
// Analytic derivatives of the inverse dynamics tau = ID(q, v, a) of the spanning tree: dtau/dq and
// dtau/dv in one forward and one backward pass plus one sweep over the (body, ancestor) pairs,
// O(nv * depth) (after Carpentier & Mansard, RSS 2018; derived here in this file's own terms).
//
// Tangent convention: the derivative with respect to q is taken along q (+) delta, delta in
// v-space, with (+) the `integrate` of configuration.hpp (a floating base moves by the
// exponential of its body twist, as Pinocchio's integrate); for 1-DoF joints that is the plain
// partial derivative. v and a are held fixed as coordinates.
//
// Everything is in the axes and at the origin of one fixed frame (SweepAxes): the world's, or the
// frame the root body occupies at this instant, which any fixed frame may be since tau and its
// derivatives do not depend on the frame they are computed in; the root's costs fewer operations
// (its columns are the joint's own S, its velocity and the gravity's direction the only things its
// pose enters). Body i has columns J_c = X(i) S_c, velocity
// V_i, acceleration A_i (the fixed frame's is minus gravity), momentum H_i = I_i V_i and force
// F_i = I_i A_i + V_i x* H_i; Ic, Hc, Fc and Bc are their sums over i's subtree, with
// B_i = V_i x* I_i - I_i (V_i x). Then tau_c = J_c . Fc_i and, for the column s of a joint on
// body b with parent p (derivation in docs/derivatives.md):
//   d/dq along s:  every body of b's subtree turns with s while p's V_p and A_p do not, so
//     dFc_i = s x* Fc_i - (Ic_i a0 + Bc_i dV + dV x* Hc_i),  dV = s x V_p,  a0 = s x A_p - dV x V_p,
//     and the column J_c of a body i in the subtree turns too, which cancels the first term:
//     dtau_c = -J_c . (Ic_i a0 + Bc_i dV + dV x* Hc_i)   (c on i in b's subtree, i = b included)
//     dtau_c =  J_c . dFc_b                                (c on a strict ancestor of b)
//   d/dv along s:  dV_i = s, dA_i = s x V_i - s x (V_p + V_b) in b's subtree, so
//     dFc_i = Bc_i s + s x* Hc_i - Ic_i (s x (V_p + V_b)), projected the same two ways.
// Per column c the products u1 = Ic_i J_c and u23 = Bc_i^T J_c - J_c x* Hc_i make each pair a
// few dot products. B is cheap: with I = [m 1, -[h]x; [h]x, I_O] and V = [v; w],
//   B = [0, -[p]x; [p]x, W],  p = m v + w x h (the linear momentum),  W = [w]x I_O - I_O [w]x - [v]x[h]x - [h]x[v]x,
// W symmetric, so Bc needs the composite momentum and a 3x3 Wc; and then
//   Bc^T J - J x* Hc = [0; Wc w_J - w_J x Hc_ang - 2 v_J x pc],  Bc x + x x* Hc = [2 w_x x pc; Wc w_x + w_x x Hc_ang].
// A geared rotor's body (rotor.hpp) is one more body of the sweep, a leaf on its
// parent whose one column N [0; w] belongs to its joint's velocity: it adds to its joint's row,
// to its parent's composites, and to dtau/dv's column of its joint (not to dtau/dq's: being
// axisymmetric, its pose does not change with its own joint's angle).
#include <vector>

#include "mbgen/algorithm/kinematics.hpp"
#include "mbgen/algorithm/rotor.hpp"

namespace mbgen {

/// The fixed frame the derivatives' sweep works in (header comment). `root`: the frame the tree's
/// root body occupies at the current q, where the root's own columns are constants (a floating
/// base's six unit twists) and products with them fold away in generated code: on talos_reduced
/// 40,331 -> 33,184 traced operations of the inverse dynamics' derivatives. Callers that read the
/// sweep's twists and columns against world quantities turn those into its axes (X[world]:
/// the ground of contact_dynamics_derivatives.hpp, the contact frames of
/// rigid_contact_derivatives.hpp). `world`: the world's, as Pinocchio's derivatives (tests).
/// A model with several bodies on the world is swept in the world's axes either way. The
/// derivatives agree between the two to round-off (test_rnea_derivatives runs both).
enum class SweepAxes { root, world };

/// Work memory and results of the dynamics derivatives (rnea_derivatives.hpp,
/// aba_derivatives.hpp). Making it allocates; the algorithms then do not.
template <typename S> struct DynamicsDerivatives {
  explicit DynamicsDerivatives(const Model& model, SweepAxes axes = SweepAxes::root);

  /// Whether the sweep runs in the root's axes (SweepAxes::root on a model with one body on the
  /// world); J, V, A, Ic, ... and the poses X are then in those, else in the world's.
  bool root_axes = false;

  // Results (nv x nv matrices; Eigen's column-major storage).
  VecX<S> tau;       ///< inverse dynamics at the (q, v, a) of the last call
  MatX<S> dtau_dq;   ///< d tau / dq along q (+) delta
  MatX<S> dtau_dv;   ///< d tau / dv
  VecX<S> ddq;       ///< forward dynamics at the (q, v, tau) of the last forward call
  MatX<S> dddq_dq;   ///< d qdd / dq = -M^-1 dtau/dq at (q, v, qdd)
  MatX<S> dddq_dv;   ///< d qdd / dv = -M^-1 dtau/dv
  MatX<S> Minv;      ///< d qdd / dtau = M^-1

  // Work of the forward derivatives (aba_derivatives.hpp).
  VecX<S> inverse_pivot;  ///< 1 / D of the mass matrix's L^T D L factor
  VecX<S> factor_entries; ///< L(k, i) for k = 0 .. nv-1 and i = k's ancestors from the nearest (factor_entry_offsets)
  MatX<S> Z, Y;           ///< Z = L^-T (column k nonzero at k's ancestors), Y = D^-1 Z

  // The sweep's bodies: the model's bodies (same indices, 0 the world) then one per rotor body.
  struct SweepBody {
    int parent = 0;        ///< sweep index of the parent
    int first_column = 0;  ///< into the column arrays
    int num_columns = 0;
    bool turns = true;     ///< its pose follows its own columns (false for a rotor)
    int rotor_joint = 0;   ///< a rotor's joint
  };
  std::vector<SweepBody> bodies;
  std::vector<int> column_v;  ///< velocity index of each column
  std::vector<Motion<S>> J, dV, a0, e;  ///< per column: J_c, s x V_p, a0, s x (V_p + V_b)
  std::vector<Force<S>> u1, w, z;  ///< per column: u1, dFc_b along q, along v
  std::vector<Vec3<S>> u23;        ///< per column: u23's angular part (its linear part is zero)
  /// Per model body its pose in the sweep's axes; X[world] the world's (the identity in its own).
  IndexedVector<BodyIndex, SE3<S>> X;
  std::vector<Motion<S>> V, A;          ///< per sweep body
  std::vector<InertiaMoments<S>> Ic;    ///< per sweep body: own, then composite inertia
  std::vector<Force<S>> Hc, Fc;
  std::vector<Mat3<S>> Wc;  ///< per sweep body: the 3x3 block of Bc (above)
};

template <typename S> DynamicsDerivatives<S>::DynamicsDerivatives(const Model& model, SweepAxes axes) {
  const int nv = model.nv();
  int bodies_on_world = 0;
  for (int k = 1; k < model.num_bodies(); ++k) bodies_on_world += model.body(BodyIndex(k)).parent == kWorldBody;
  root_axes = axes == SweepAxes::root && bodies_on_world == 1;
  tau = VecX<S>::Zero(nv);
  ddq = VecX<S>::Zero(nv);
  for (MatX<S>* m : {&dtau_dq, &dtau_dv, &dddq_dq, &dddq_dv, &Minv, &Z, &Y}) *m = MatX<S>::Zero(nv, nv);
  inverse_pivot = VecX<S>::Zero(nv);
  int entries = 0;
  for (int k = 0; k < nv; ++k)
    for (int i = model.velocity_parent(k); i >= 0; i = model.velocity_parent(i)) ++entries;
  factor_entries = VecX<S>::Zero(entries);
  bodies.resize(static_cast<std::size_t>(model.num_bodies()));
  for (int k = 1; k < model.num_bodies(); ++k) {
    const Body& body = model.body(BodyIndex(k));
    const Joint& joint = model.joint(body.joint);
    SweepBody& b = bodies[static_cast<std::size_t>(k)];
    b.parent = body.parent.value();
    b.first_column = static_cast<int>(column_v.size());
    b.num_columns = joint.nv;
    for (int c = 0; c < joint.nv; ++c) column_v.push_back(joint.idx_v + c);
  }
  for (int k = 1; k < model.num_bodies(); ++k) {
    const Body& body = model.body(BodyIndex(k));
    const Joint& joint = model.joint(body.joint);
    if (!joint.has_rotor_body()) continue;
    SweepBody rotor;
    rotor.parent = body.parent.value();
    rotor.first_column = static_cast<int>(column_v.size());
    rotor.num_columns = 1;
    rotor.turns = false;
    rotor.rotor_joint = body.joint.value();
    column_v.push_back(joint.idx_v);
    bodies.push_back(rotor);
  }
  const std::size_t nb = bodies.size(), nc = column_v.size();
  for (auto* m : {&J, &dV, &a0, &e}) m->assign(nc, Motion<S>::Zero());
  for (auto* f : {&u1, &w, &z}) f->assign(nc, Force<S>::Zero());
  u23.assign(nc, Vec3<S>::Zero());
  X = IndexedVector<BodyIndex, SE3<S>>(static_cast<std::size_t>(model.num_bodies()), SE3<S>::Identity());
  V.assign(nb, Motion<S>::Zero());
  A.assign(nb, Motion<S>::Zero());
  Ic.assign(nb, InertiaMoments<S>{});
  Hc.assign(nb, Force<S>::Zero());
  Fc.assign(nb, Force<S>::Zero());
  Wc.assign(nb, Mat3<S>::Zero());
}

namespace detail {
/// W = [w]x I_O - I_O [w]x - [v]x[h]x - [h]x[v]x of a body (or rotor) with moments I moving with
/// V = [v; w]: the block of B = V x* I - I (V x) that is not the momentum's (header comment).
/// Symmetric; [a]x[b]x + [b]x[a]x = a b^T + b a^T - 2 (a . b) 1.
template <typename S> Mat3<S> inertia_velocity_block(const InertiaMoments<S>& I, const Motion<S>& V) {
  const Vec3<S>& w = V.angular;
  const Vec3<S>& v = V.linear;
  const Vec3<S>& h = I.first_moment;
  const Mat3<S> wI = skew<S>(w) * I.rotational;  // [w]x I_O; I_O [w]x = -(wI)^T
  const S vh = v.dot(h);
  Mat3<S> W;
  for (int r = 0; r < 3; ++r)
    for (int c = r; c < 3; ++c) {
      S x = wI(r, c) + wI(c, r) - v[r] * h[c] - h[r] * v[c];
      if (r == c) x += S(2) * vh;
      W(r, c) = x;
      W(c, r) = x;
    }
  return W;
}

/// Bc x + x x* Hc = [2 w_x x pc; Wc w_x + w_x x Hc_ang] (pc = Hc.linear).
template <typename S> Force<S> coriolis_product(const Mat3<S>& Wc, const Force<S>& Hc, const Motion<S>& x) {
  return Force<S>{S(2) * x.angular.cross(Hc.linear), Wc * x.angular + x.angular.cross(Hc.angular)};
}

/// Bc^T J - J x* Hc = [0; Wc w_J - w_J x Hc_ang - 2 v_J x pc]: the angular part (the linear is zero).
template <typename S> Vec3<S> coriolis_transpose_product(const Mat3<S>& Wc, const Force<S>& Hc, const Motion<S>& J) {
  return Wc * J.angular - J.angular.cross(Hc.angular) - S(2) * J.linear.cross(Hc.linear);
}
}  // namespace detail

/// dtau/dq and dtau/dv of the spanning tree's inverse dynamics at (q, v, a), and tau itself (rnea()
/// of the same arguments), in d. Leaves the bodies' poses in the sweep's axes in d.X (with
/// SweepAxes::world: their world poses) and their placements in data.X_PB. No allocation.
template <typename S>
void inverse_dynamics_derivatives(const Model& model, Data<S>& data, DynamicsDerivatives<S>& d, const ConstVecRef<S>& q,
                                  const ConstVecRef<S>& v, const ConstVecRef<S>& a) {
  const int nb = model.num_bodies();
  const int ns = static_cast<int>(d.bodies.size());
  const auto at = [](int k) { return static_cast<std::size_t>(k); };
  // Forward: poses, columns, velocities, accelerations and each body's own terms. In the root's
  // axes the root sits at the identity and the gravity turns into them instead.
  // d.X[world] is the world's pose in them, which a rotor on the world and the contacts read.
  Vec3<S> gravity = model.gravity.cast<S>();
  d.X[kWorldBody] = SE3<S>::Identity();
  if (d.root_axes) {
    detail::place_in_parent<S>(model, data, q.data(), BodyIndex(1));
    d.X[kWorldBody] = data.X_PB[BodyIndex(1)].inverse();
    gravity = d.X[kWorldBody].rotation * gravity;
  }
  d.V[0] = Motion<S>::Zero();
  d.A[0] = Motion<S>{-gravity, Vec3<S>::Zero()};
  for (int k = 1; k < ns; ++k) {
    const auto& sb = d.bodies[at(k)];
    const int c0 = sb.first_column;
    Motion<S> V = d.V[at(sb.parent)], A = d.A[at(sb.parent)];
    if (k < nb) {
      const BodyIndex i(k);
      const Body& body = model.body(i);
      const Joint& joint = model.joint(body.joint);
      if (d.root_axes && k == 1) {
        d.X[i] = SE3<S>::Identity();
      } else {
        detail::place_in_parent<S>(model, data, q.data(), i);
        d.X[i] = d.X[body.parent] * data.X_PB[i];
      }
      for (int col = 0; col < joint.nv; ++col) {
        d.J[at(c0 + col)] = d.X[i].act(joint_subspace_column<S>(joint, col));
        V += d.J[at(c0 + col)] * v[joint.idx_v + col];
        A += d.J[at(c0 + col)] * a[joint.idx_v + col];
      }
      d.Ic[at(k)] = InertiaMoments<S>::of(body.inertia, d.X[i]);
    } else {
      // A rotor: the column N [0; w] in the sweep's axes, its spin inertia I_r w w^T (rotor.hpp).
      const Joint& joint = model.joint(JointIndex(sb.rotor_joint));
      const Vec3<S> w = d.X[BodyIndex(sb.parent)].rotation * rotor_axis_in_parent(joint).template cast<S>();
      d.J[at(c0)] = Motion<S>{Vec3<S>::Zero(), w * S(joint.rotor_gear_ratio)};
      V += d.J[at(c0)] * v[joint.idx_v];
      A += d.J[at(c0)] * a[joint.idx_v];
      InertiaMoments<S> I;
      I.rotational = (w * w.transpose()) * S(joint.rotor_inertia);
      d.Ic[at(k)] = I;
    }
    A += d.V[at(sb.parent)].cross(V);  // sum_c (V x J_c) v_c = V x (V - V_p) = V_p x V
    d.V[at(k)] = V;
    d.A[at(k)] = A;
    d.Hc[at(k)] = d.Ic[at(k)] * V;
    d.Fc[at(k)] = d.Ic[at(k)] * A + V.cross(d.Hc[at(k)]);
    d.Wc[at(k)] = detail::inertia_velocity_block<S>(d.Ic[at(k)], V);
  }
  // Backward: the subtree sums (children have larger indices, rotors the largest).
  for (int k = ns - 1; k >= 1; --k) {
    const int p = d.bodies[at(k)].parent;
    if (p == 0) continue;
    d.Ic[at(p)] += d.Ic[at(k)];
    d.Hc[at(p)] += d.Hc[at(k)];
    d.Fc[at(p)] += d.Fc[at(k)];
    d.Wc[at(p)] += d.Wc[at(k)];
  }
  // Per column: tau, u1, u23 and the pair terms of the columns' own joint.
  d.tau.setZero();
  for (int k = 1; k < ns; ++k) {
    const auto& sb = d.bodies[at(k)];
    const Motion<S>& Vp = d.V[at(sb.parent)];
    const Motion<S>& Ap = d.A[at(sb.parent)];
    for (int c = sb.first_column; c < sb.first_column + sb.num_columns; ++c) {
      const Motion<S>& s = d.J[at(c)];
      d.tau[d.column_v[at(c)]] += s.dot(d.Fc[at(k)]);
      d.u1[at(c)] = d.Ic[at(k)] * s;
      d.u23[at(c)] = detail::coriolis_transpose_product<S>(d.Wc[at(k)], d.Hc[at(k)], s);
      if (sb.turns) {
        d.dV[at(c)] = s.cross(Vp);
        d.a0[at(c)] = s.cross(Ap) - d.dV[at(c)].cross(Vp);
        d.w[at(c)] = s.cross(d.Fc[at(k)]) - d.Ic[at(k)] * d.a0[at(c)] -
                     detail::coriolis_product<S>(d.Wc[at(k)], d.Hc[at(k)], d.dV[at(c)]);
      }
      d.e[at(c)] = s.cross(Vp + d.V[at(k)]);
      d.z[at(c)] = detail::coriolis_product<S>(d.Wc[at(k)], d.Hc[at(k)], s) - d.Ic[at(k)] * d.e[at(c)];
    }
  }
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    if (joint.armature != 0) d.tau[joint.idx_v] += S(joint.armature) * a[joint.idx_v];
  }
  // The pairs (i, b), b = i or an ancestor of i.
  d.dtau_dq.setZero();
  d.dtau_dv.setZero();
  for (int i = 1; i < ns; ++i) {
    const auto& si = d.bodies[at(i)];
    for (int b = i; b != 0; b = d.bodies[at(b)].parent) {
      const auto& sb = d.bodies[at(b)];
      for (int c = si.first_column; c < si.first_column + si.num_columns; ++c) {
        const int row = d.column_v[at(c)];
        for (int k = sb.first_column; k < sb.first_column + sb.num_columns; ++k) {
          const int col = d.column_v[at(k)];
          if (sb.turns) d.dtau_dq(row, col) -= d.a0[at(k)].dot(d.u1[at(c)]) + d.dV[at(k)].angular.dot(d.u23[at(c)]);
          d.dtau_dv(row, col) += d.J[at(k)].angular.dot(d.u23[at(c)]) - d.e[at(k)].dot(d.u1[at(c)]);
        }
      }
      if (b == i) continue;
      for (int c = sb.first_column; c < sb.first_column + sb.num_columns; ++c) {
        const int row = d.column_v[at(c)];
        for (int k = si.first_column; k < si.first_column + si.num_columns; ++k) {
          const int col = d.column_v[at(k)];
          if (si.turns) d.dtau_dq(row, col) += d.J[at(c)].dot(d.w[at(k)]);
          d.dtau_dv(row, col) += d.J[at(c)].dot(d.z[at(k)]);
        }
      }
    }
  }
}

}  // namespace mbgen
