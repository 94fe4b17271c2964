#pragma once
// The articulated-body algorithm's step for a sub-system (loop_closure.hpp): the bodies of a set
// of kinematic loops treated as one aggregate body whose "joint" has the sub-system's
// independent coordinates y (constraint embedding, Jain 2011; the thesis' sub-systems). aba()
// calls these in place of the per-joint step for the bodies of a sub-system.
//
// Within a sub-system the tree coordinates move as qd_s = G yd and qdd_s = G ydd + g (G, g from
// the closure maps, in Data::subsystem). With H_b = d a_b / d ydd (body b's acceleration per unit
// ydd) and bias_b (its acceleration at ydd = 0 with the root at rest), every body accelerates as
//   a_b = X_br a_r + H_b ydd + bias_b.
// Virtual power with admissible variations (delta qd_s = G delta yd) gives, over the bodies of
// the sub-system with their articulated inertias IA_b and bias forces pA_b (which already hold
// every subtree that hangs off them),
//   D ydd = u - U^T a_r,  D = sum H_b^T IA_b H_b,  U = sum X_br^T IA_b H_b,
//   u = G^T tau_s - sum H_b^T (IA_b bias_b + pA_b)   (drives' armature adds G^T A G to D, -G^T A g to u),
// and the force the root feels, f = (I_S - U D^-1 U^T) a_r + p_S + U D^-1 u with
// I_S = sum X_br^T IA_b X_br and p_S = sum X_br^T (IA_b bias_b + pA_b). The sums over X_br^T
// are accumulated leaves to root inside the sub-system, as the tree ABA does, so the work is
// O(m p^2 + p^3) for m bodies and p independent coordinates: the whole stays O(n).
// The closure constraints never appear: G carries them, so redundant closure rows cost nothing.
#include "mbgen/algorithm/small_ldlt.hpp"
#include "mbgen/algorithm/kinematics.hpp"

namespace mbgen::detail {

/// Column `col` of a 6 x n block stored at rows 6 b .. 6 b + 5 of M, as a motion or force.
template <typename S> Vec6<S> block_column(const MatX<S>& M, int b, int col) {
  return M.template block<6, 1>(6 * b, col);
}

/// Backward step of sub-system `s` (aba pass 2), run once all bodies outside it with a larger
/// index are done. Adds the sub-system's articulated inertia and bias force to its root.
template <typename S>
void subsystem_backward(const Model& model, Data<S>& data, int s, const ConstVecRef<S>& tau) {
  const SubSystem& sub = model.subsystems[static_cast<std::size_t>(s)];
  SubSystemWork<S>& w = data.subsystem[static_cast<std::size_t>(s)];
  const int m = static_cast<int>(sub.bodies.size());
  const int p = static_cast<int>(sub.independent.size());

  // Root to leaves inside the sub-system: H_b and bias_b, from the parent's (zero at the root).
  for (int j = 0; j < m; ++j) {
    const BodyIndex b = sub.bodies[static_cast<std::size_t>(j)];
    const Joint& joint = model.joint(model.body(b).joint);
    const int parent = w.parent_local[static_cast<std::size_t>(j)];
    for (int col = 0; col < p; ++col) {
      const S rate = w.G(j, col);
      Motion<S> h = joint_velocity<S>(joint, &rate);
      if (parent >= 0)
        h = h + motion_parent_to_child<S>(joint, data.X_J[b], Motion<S>::from_vector(block_column<S>(w.H, parent, col)));
      w.H.template block<6, 1>(6 * j, col) = h.vector();
    }
    const S g_j = w.g[j];
    Motion<S> bias = joint_velocity<S>(joint, &g_j) + data.c[b];
    if (parent >= 0) bias = bias + motion_parent_to_child<S>(joint, data.X_J[b], Motion<S>::from_vector(w.bias.col(parent)));
    w.bias.col(j) = bias.vector();
  }

  // Per body: F_b = IA_b H_b (kept in w.F), D += H_b^T F_b, P_b = IA_b bias_b + pA_b (in pA),
  // u -= H_b^T P_b. The drives' reflected inertias join through G.
  for (int col = 0; col < p; ++col) {
    S u_col = S(0);
    for (int j = 0; j < static_cast<int>(sub.coordinates.size()); ++j) u_col += w.G(j, col) * tau[sub.coordinates[static_cast<std::size_t>(j)]];
    w.u[col] = u_col;
  }
  w.D.setZero();
  for (int j = 0; j < m; ++j) {
    const BodyIndex b = sub.bodies[static_cast<std::size_t>(j)];
    const Joint& joint = model.joint(model.body(b).joint);
    for (int col = 0; col < p; ++col) w.F.template block<6, 1>(6 * j, col) = data.IA[b] * block_column<S>(w.H, j, col);
    const Vec6<S> P = data.IA[b] * w.bias.col(j) + data.pA[b].vector();
    data.pA[b] = Force<S>::from_vector(P);
    for (int r = 0; r < p; ++r) {
      w.u[r] -= block_column<S>(w.H, j, r).dot(P);
      for (int col = r; col < p; ++col) w.D(r, col) += block_column<S>(w.H, j, r).dot(block_column<S>(w.F, j, col));
    }
    if (joint.armature != 0)  // the drive's force armature qdd_j = armature (G_j ydd + g_j)
      for (int r = 0; r < p; ++r) {
        w.u[r] -= S(joint.armature) * w.G(j, r) * w.g[j];
        for (int col = r; col < p; ++col) w.D(r, col) += S(joint.armature) * w.G(j, r) * w.G(j, col);
      }
  }
  for (int r = 0; r < p; ++r)
    for (int col = 0; col < r; ++col) w.D(r, col) = w.D(col, r);

  // Leaves to root inside the sub-system: I_S, U = sum X^T F_b, p_S, gathered in the root frame.
  Mat6<S> I_S = Mat6<S>::Zero();
  Vec6<S> p_S = Vec6<S>::Zero();
  w.U.setZero();
  for (int j = m - 1; j >= 0; --j) {
    const BodyIndex b = sub.bodies[static_cast<std::size_t>(j)];
    const Joint& joint = model.joint(model.body(b).joint);
    const int parent = w.parent_local[static_cast<std::size_t>(j)];
    const Mat6<S> I_up = inertia_child_to_parent<S>(joint, data.X_J[b], data.IA[b]);
    const Vec6<S> p_up = force_child_to_parent<S>(joint, data.X_J[b], data.pA[b]).vector();
    if (parent >= 0) {
      const BodyIndex pb = sub.bodies[static_cast<std::size_t>(parent)];
      data.IA[pb] += I_up;
      data.pA[pb] = Force<S>::from_vector(data.pA[pb].vector() + p_up);
    } else {
      I_S += I_up;
      p_S += p_up;
    }
    for (int col = 0; col < p; ++col) {
      const Vec6<S> F_up = force_child_to_parent<S>(joint, data.X_J[b], Force<S>::from_vector(block_column<S>(w.F, j, col))).vector();
      if (parent >= 0) w.F.template block<6, 1>(6 * parent, col) += F_up;
      else w.U.col(col) += F_up;
    }
  }

  ldlt_factor<S>(w.D, p, w.D_factor);
  if (sub.root == kWorldBody) return;  // the world needs no articulated inertia
  // IA_root += I_S - U D^-1 U^T ; pA_root += p_S + U D^-1 u.
  MatX<S>& UDinv = w.UDinv;  // row r: (D^-1 U.row(r)^T)^T
  for (int r = 0; r < 6; ++r) {
    for (int col = 0; col < p; ++col) w.scratch[col] = w.U(r, col);
    ldlt_solve<S>(w.D_factor, p, w.scratch.data());
    for (int col = 0; col < p; ++col) UDinv(r, col) = w.scratch[col];
  }
  Mat6<S> Ia;
  for (int r = 0; r < 6; ++r)
    for (int c = r; c < 6; ++c) {
      S x = I_S(r, c);
      for (int k = 0; k < p; ++k) x -= UDinv(r, k) * w.U(c, k);
      Ia(r, c) = x;
      Ia(c, r) = x;
    }
  Vec6<S> pa = p_S;
  for (int r = 0; r < 6; ++r)
    for (int k = 0; k < p; ++k) pa[r] += UDinv(r, k) * w.u[k];
  data.IA[sub.root] += Ia;
  data.pA[sub.root] = Force<S>::from_vector(data.pA[sub.root].vector() + pa);
}

/// Forward step of sub-system `s` (aba pass 3), once its root's acceleration is known: ydd, the
/// tree accelerations of its coordinates (into data.ddq) and its bodies' accelerations.
template <typename S> void subsystem_forward(const Model& model, Data<S>& data, int s) {
  const SubSystem& sub = model.subsystems[static_cast<std::size_t>(s)];
  SubSystemWork<S>& w = data.subsystem[static_cast<std::size_t>(s)];
  const int p = static_cast<int>(sub.independent.size());
  const Vec6<S> a_root = data.a[sub.root].vector();
  for (int col = 0; col < p; ++col) w.ydd[col] = w.u[col] - w.U.col(col).dot(a_root);
  ldlt_solve<S>(w.D_factor, p, w.ydd.data());
  for (int j = 0; j < static_cast<int>(sub.coordinates.size()); ++j) {
    S qdd = w.g[j];
    for (int col = 0; col < p; ++col) qdd += w.G(j, col) * w.ydd[col];
    data.ddq[sub.coordinates[static_cast<std::size_t>(j)]] = qdd;
  }
  for (std::size_t j = 0; j < sub.bodies.size(); ++j) {
    const BodyIndex b = sub.bodies[j];
    const Body& body = model.body(b);
    const Joint& joint = model.joint(body.joint);
    data.a[b] = motion_parent_to_child<S>(joint, data.X_J[b], data.a[body.parent]) +
                joint_velocity<S>(joint, data.ddq.data() + joint.idx_v) + data.c[b];
  }
}

}  // namespace mbgen::detail
