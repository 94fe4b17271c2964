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
#include "mbgen/algorithm/kinematics.hpp"
#include "mbgen/algorithm/rotor.hpp"
#include "mbgen/algorithm/small_ldlt.hpp"

namespace mbgen::detail {

/// Column `col` of a 6 x n block stored at rows 6 b .. 6 b + 5 of M, as a motion or force.
template <typename S> Vec6<S> block_column(const MatX<S>& M, int b, int col) {
  return M.template block<6, 1>(6 * b, col);
}

/// Where a rotor body's terms go: its parent P's slots when P is a body of the sub-system, else
/// the sums at the sub-system's root (P is the root; same frame, so no transform either way).
template <typename S> struct RotorTarget {
  Mat6<S>& inertia;    ///< IA_P, or I_S
  Vec3<S>& moment;     ///< angular part of pA_P (already IA bias + pA, see subsystem_backward), or of p_S
  MatX<S>& gathered;   ///< w.F, or w.U
  int first_row;       ///< 6 parent_local, or 0
};

/// The rotor body of the joint moving sub-system body j (rotor.hpp: fixed in the joint's parent P,
/// spinning about w at N qd_j, axial inertia I_r only). It is one more body of the sub-system,
/// with H_R = H_P + N [w; 0] G_j (rows of G: coordinate j). Its spin acceleration is
///   w . alpha_R = w . (X a_root)_ang + h ydd + beta,  h = w . H_P,ang + N G_j,  beta = w . bias_P,ang + N g_j
/// (the velocity-product term w_P x (N qd w) is normal to w), and its force in P is
/// F_R = [0; I_r (w . alpha_R) w + gyro], gyro = I_r (w . w_R)(w_P x w). As a body of the
/// sub-system it adds (I_R H_R = [0; I_r w h], H_R,ang^T gyro = H_P,ang^T gyro since w . gyro = 0):
///   D += I_r h^T h,  u -= I_r beta h^T + H_P,ang^T gyro,  F_P += [0; I_r w h],
///   IA_P += I_R,  pA_P += [0; I_r beta w + gyro]  (carried to the root with P's own terms).
/// P outside the sub-system is its root: H_P = 0 and bias_P = 0 there (the root's acceleration
/// enters through U). The tree ABA's add_rotor_to_parent is the same body with p = 1, G = 1.
template <typename S>
void add_subsystem_rotor(const Model& model, const Data<S>& data, SubSystemWork<S>& w, int j, int parent, const Joint& joint,
                         const S& qd, const RotorTarget<S>& target) {
  const int p = static_cast<int>(w.G.cols());
  const BodyIndex P = model.body(joint.child).parent;
  const Vec3<S> axis = rotor_axis_in_parent(joint).template cast<S>();
  const S N(joint.rotor_gear_ratio), I(joint.rotor_inertia);
  const S spin_rate = axis.dot(data.v[P].angular) + N * qd;
  const Vec3<S> gyro = data.v[P].angular.cross(axis) * (I * spin_rate);
  S beta = N * w.g[j];
  if (parent >= 0) beta += axis.dot(w.bias.col(parent).template tail<3>());
  for (int r = 0; r < p; ++r) {
    w.scratch[r] = N * w.G(j, r);  // h
    if (parent >= 0) w.scratch[r] += axis.dot(w.H.template block<3, 1>(6 * parent + 3, r));
  }
  for (int r = 0; r < p; ++r) {
    w.u[r] -= I * beta * w.scratch[r];
    if (parent >= 0) w.u[r] -= w.H.template block<3, 1>(6 * parent + 3, r).dot(gyro);
    for (int col = r; col < p; ++col) w.D(r, col) += I * w.scratch[r] * w.scratch[col];
    target.gathered.template block<3, 1>(target.first_row + 3, r) += axis * (I * w.scratch[r]);
  }
  target.inertia.template bottomRightCorner<3, 3>() += (axis * axis.transpose()) * I;
  target.moment += axis * (I * beta) + gyro;
}

/// Backward step of sub-system `s` (aba pass 2), run once all bodies outside it with a larger
/// index are done. Adds the sub-system's articulated inertia and bias force to its root.
template <typename S>
void subsystem_backward(const Model& model, Data<S>& data, int s, const ConstVecRef<S>& v, const ConstVecRef<S>& tau) {
  const SubSystem& sub = model.subsystems[static_cast<std::size_t>(s)];
  SubSystemWork<S>& w = data.subsystem[static_cast<std::size_t>(s)];
  const SubSystemLayout& layout = model.structure().subsystems[static_cast<std::size_t>(s)];
  const int m = static_cast<int>(sub.bodies.size());
  const int p = static_cast<int>(sub.independent.size());

  // Root to leaves inside the sub-system: H_b and bias_b, from the parent's (zero at the root).
  for (int j = 0; j < m; ++j) {
    const BodyIndex b = sub.bodies[static_cast<std::size_t>(j)];
    const Joint& joint = model.joint(model.body(b).joint);
    const int parent = layout.parent_local[static_cast<std::size_t>(j)];
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
  // u -= H_b^T P_b. The drives' reflected inertias join through G, their rotor bodies as bodies
  // fixed in the joint's parent (add_subsystem_rotor), after the parent's own terms.
  Mat6<S> I_S = Mat6<S>::Zero();  // the root's share, gathered leaves to root below
  Force<S> p_S = Force<S>::Zero();
  w.U.setZero();
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
    if (joint.has_rotor_body()) {
      const int parent = layout.parent_local[static_cast<std::size_t>(j)];
      const RotorTarget<S> target = parent >= 0 ? RotorTarget<S>{data.IA[sub.bodies[static_cast<std::size_t>(parent)]],
                                                                 data.pA[sub.bodies[static_cast<std::size_t>(parent)]].angular,
                                                                 w.F, 6 * parent}
                                                : RotorTarget<S>{I_S, p_S.angular, w.U, 0};
      add_subsystem_rotor<S>(model, data, w, j, parent, joint, v[joint.idx_v], target);
    }
  }
  for (int r = 0; r < p; ++r)
    for (int col = 0; col < r; ++col) w.D(r, col) = w.D(col, r);

  // Leaves to root inside the sub-system: I_S, U = sum X^T F_b, p_S, gathered in the root frame.
  // A rigid body's gathered inertia (SubSystemLayout::rigid: the drive linkage's rods, nuts and
  // housings) is a rigid body's, so it moves as 10 mass moments (a rotation and a parallel-axis
  // shift) and becomes a 6x6 only where it joins a body that is not rigid; the 6x6 congruence
  // costs about three times as much, and traced it does not see that the mass block stays m 1.
  // data.IA of a rigid body keeps its own inertia only.
  for (int j = 0; j < m; ++j)
    if (layout.rigid[static_cast<std::size_t>(j)])
      w.moments[static_cast<std::size_t>(j)] = InertiaMoments<S>::of_body(model.body(sub.bodies[static_cast<std::size_t>(j)]).inertia);
  for (int j = m - 1; j >= 0; --j) {
    const BodyIndex b = sub.bodies[static_cast<std::size_t>(j)];
    const Joint& joint = model.joint(model.body(b).joint);
    const int parent = layout.parent_local[static_cast<std::size_t>(j)];
    const Force<S> p_up = force_child_to_parent<S>(joint, data.X_J[b], data.pA[b]);
    Mat6<S>& I_target = parent >= 0 ? data.IA[sub.bodies[static_cast<std::size_t>(parent)]] : I_S;
    if (!layout.rigid[static_cast<std::size_t>(j)]) {
      I_target += inertia_child_to_parent<S>(joint, data.X_J[b], data.IA[b]);
    } else {
      const InertiaMoments<S> up = moments_child_to_parent<S>(joint, data.X_J[b], w.moments[static_cast<std::size_t>(j)]);
      if (parent >= 0 && layout.rigid[static_cast<std::size_t>(parent)]) w.moments[static_cast<std::size_t>(parent)] += up;
      else I_target += up.matrix();
    }
    if (parent >= 0) {
      const BodyIndex pb = sub.bodies[static_cast<std::size_t>(parent)];
      data.pA[pb] = data.pA[pb] + p_up;
    } else {
      p_S = p_S + p_up;
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
  Vec6<S> pa = p_S.vector();
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
