#pragma once
// Articulated-body algorithm (Featherstone): forward dynamics in O(n).
#include "mbgen/algorithm/kinematics.hpp"
#include "mbgen/algorithm/rotor.hpp"
#include "mbgen/algorithm/small_ldlt.hpp"
#include "mbgen/algorithm/subsystem_aba.hpp"
#include "mbgen/algorithm/subsystem_maps.hpp"

namespace mbgen {

namespace detail {
/// The rotor body of the 1-DoF joint moving body i (rotor.hpp) in the ABA's backward pass. With
/// the rotor, the joint drives the pair (child, rotor): U_t = X^T U + N r in the parent frame,
/// r = I_R S_R = [0; I_r w], and D already holds N^2 I_r. The child's part, X^T (IA - U U^T/D) X
/// and X^T (pA + Ia c + U u/D), is added by the caller; this adds the rest:
///   IA_P += I_R - (N (X^T U) r^T + N r (X^T U)^T + N^2 r r^T) / D
///   pA_P += pA_R + N r (u - U^T c) / D,   pA_R = v_R x* I_R v_R  (I_R c_R = 0 for an axisymmetric rotor).
template <typename S>
void add_rotor_to_parent(const Model& model, Data<S>& data, BodyIndex i, const S& qd, const S& u_minus_Uc) {
  const Body& body = model.body(i);
  const Joint& joint = model.joint(body.joint);
  const BodyIndex p = body.parent;
  const S Dinv = data.D_inv[i](0, 0);
  const Vec6<S> XU = force_child_to_parent<S>(joint, data.X_J[i], Force<S>::from_vector(data.U[i].col(0))).vector();
  const Vec6<S> Nr = rotor_momentum_per_rate<S>(joint).vector() * S(joint.rotor_gear_ratio);
  data.IA[p] += rotor_inertia_in_parent<S>(joint) -
                (Nr * XU.transpose() + XU * Nr.transpose() + Nr * Nr.transpose()) * Dinv;
  // pA_R: the rotor's gyroscopic force (its force at zero accelerations).
  data.pA[p] += rotor_force<S>(joint, data.v[p], Motion<S>::Zero(), qd, S(0));
  data.pA[p] += Force<S>::from_vector(Nr * (u_minus_Uc * Dinv));
}
}  // namespace detail

namespace detail {
/// Pass 1 of aba() (below), root to leaves: joint transforms, body velocities data.v (body
/// frame), velocity-product terms, and the bias forces pA = v x* I v. External forces on the
/// bodies (the ground's contacts: contact_dynamics.hpp) are subtracted from data.pA between this
/// pass and aba_force_passes.
template <typename S> void aba_velocity_pass(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  data.v[kWorldBody] = Motion<S>::Zero();
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    const Body& body = model.body(i);
    const Joint& joint = model.joint(body.joint);
    data.X_J[i] = joint_motion_transform<S>(joint, q.data() + joint.idx_q);
    Motion<S> vj = joint_velocity<S>(joint, v.data() + joint.idx_v);
    data.v[i] = motion_parent_to_child<S>(joint, data.X_J[i], data.v[body.parent]) + vj;
    data.c[i] = data.v[i].cross(vj);
    const Inertia<S> I = body.inertia.cast<S>();
    data.IA[i] = I.matrix();
    data.pA[i] = data.v[i].cross(I * data.v[i]);
  }
}

/// Passes 2 and 3 of aba(): articulated inertias and bias forces leaves to root, then the
/// accelerations root to leaves, into data.ddq. Needs aba_velocity_pass at the same (q, v).
template <typename S> const VecX<S>& aba_force_passes(const Model& model, Data<S>& data, const ConstVecRef<S>& v, const ConstVecRef<S>& tau) {
  // Pass 2, leaves to root: articulated inertias and bias forces.
  for (int k = model.num_bodies() - 1; k >= 1; --k) {
    const BodyIndex i(k);
    if (const int s = model.structure().subsystem_of_body[i]; s >= 0) {  // a sub-system: once, at its first body
      if (model.subsystems[static_cast<std::size_t>(s)].bodies.front() == i) detail::subsystem_backward<S>(model, data, s, v, tau);
      continue;
    }
    const Body& body = model.body(i);
    const Joint& joint = model.joint(body.joint);
    const int n = joint.nv;
    Mat6<S>& U = data.U[i];
    Mat6<S>& Dinv = data.D_inv[i];
    Vec6<S>& u = data.u[i];
    S proj[6];
    joint_project<S>(joint, data.pA[i], proj);
    for (int col = 0; col < n; ++col) {
      U.col(col) = data.IA[i] * joint_subspace_column<S>(joint, col).vector();
      u[col] = tau[joint.idx_v + col] - proj[col];
    }
    if (n == 1) {
      S D = joint_subspace_column<S>(joint, 0).vector().dot(U.col(0));
      if (joint.armature != 0 || joint.has_rotor_body()) D += S(drive_diagonal_inertia(joint));
      Dinv(0, 0) = S(1) / D;
    } else {
      Mat6<S> D;
      for (int col = 0; col < n; ++col) {
        S col_proj[6];
        joint_project<S>(joint, Force<S>::from_vector(U.col(col)), col_proj);
        for (int r = 0; r < n; ++r) D(r, col) = col_proj[r];
      }
      ldlt_factor<S>(D, n, Dinv);  // multi-DoF: Dinv holds the factor of D (small_ldlt.hpp)
    }
    if (body.parent == kWorldBody) continue;
    // Ia = IA - U D^-1 U^T ; pa = pA + Ia c + U D^-1 u
    Mat6<S> UDinv;  // U D^-1, row r solving D x = U.row(r)^T
    Vec6<S> Dinv_u;
    if (n == 1) {
      UDinv.col(0) = U.col(0) * Dinv(0, 0);
      Dinv_u[0] = Dinv(0, 0) * u[0];
    } else {
      for (int r = 0; r < 6; ++r) {
        S x[6];
        for (int c = 0; c < n; ++c) x[c] = U(r, c);
        ldlt_solve<S>(Dinv, n, x);
        for (int c = 0; c < n; ++c) UDinv(r, c) = x[c];
      }
      for (int c = 0; c < n; ++c) Dinv_u[c] = u[c];
      ldlt_solve<S>(Dinv, n, Dinv_u.data());
    }
    Mat6<S> Ia;
    for (int r = 0; r < 6; ++r)
      for (int c = r; c < 6; ++c) {  // symmetric: upper triangle, mirrored
        Ia(r, c) = data.IA[i](r, c) - UDinv.row(r).head(n).dot(U.row(c).head(n));
        Ia(c, r) = Ia(r, c);
      }
    // Ia S = U - U D^-1 S^T U = 0 when D = S^T U (no drive inertia on the diagonal). For an axis
    // along a coordinate axis that is a row and a column of Ia, exact zeros that the rounding of
    // the lines above only approximates: set them, and the move to the parent and Ia c skip them
    // (a symbolic scalar folds the zeros; 15 of Ia's 21 entries remain).
    if (const int e = joint_subspace_coordinate(joint); n == 1 && e >= 0 && joint.armature == 0 && !joint.has_rotor_body()) {
      Ia.row(e).setZero();
      Ia.col(e).setZero();
    }
    Vec6<S> pa = data.pA[i].vector() + Ia * data.c[i].vector() + U.leftCols(n) * Dinv_u.head(n);
    data.IA[body.parent] += inertia_child_to_parent<S>(joint, data.X_J[i], Ia);
    data.pA[body.parent] += force_child_to_parent<S>(joint, data.X_J[i], Force<S>::from_vector(pa));
    if (joint.has_rotor_body()) detail::add_rotor_to_parent<S>(model, data, i, v[joint.idx_v], u[0] - U.col(0).dot(data.c[i].vector()));
  }
  // Pass 3, root to leaves: accelerations.
  data.a[kWorldBody] = Motion<S>{-model.gravity.cast<S>(), Vec3<S>::Zero()};
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    if (const int s = model.structure().subsystem_of_body[i]; s >= 0) {
      if (model.subsystems[static_cast<std::size_t>(s)].bodies.front() == i) detail::subsystem_forward<S>(model, data, s);
      continue;
    }
    const Body& body = model.body(i);
    const Joint& joint = model.joint(body.joint);
    const int n = joint.nv;
    Motion<S> a_prime = motion_parent_to_child<S>(joint, data.X_J[i], data.a[body.parent]) + data.c[i];
    Vec6<S> rhs;
    for (int r = 0; r < n; ++r) rhs[r] = data.u[i][r] - data.U[i].col(r).dot(a_prime.vector());
    if (joint.has_rotor_body())  // the rotor's reaction to the parent's acceleration
      rhs[0] -= S(joint.rotor_gear_ratio) * rotor_momentum_per_rate<S>(joint).angular.dot(data.a[body.parent].angular);
    S* qdd = data.ddq.data() + joint.idx_v;
    if (n == 1) {
      qdd[0] = data.D_inv[i](0, 0) * rhs[0];
    } else {
      for (int r = 0; r < n; ++r) qdd[r] = rhs[r];
      ldlt_solve<S>(data.D_inv[i], n, qdd);
    }
    data.a[i] = a_prime + joint_velocity<S>(joint, qdd);
  }
  return data.ddq;
}

/// The recursion of aba() (below), with each sub-system's maps G, g already in data.subsystem.
template <typename S>
const VecX<S>& aba_recursion(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                             const ConstVecRef<S>& tau) {
  aba_velocity_pass<S>(model, data, q, v);
  return aba_force_passes<S>(model, data, v, tau);
}

}  // namespace detail

/// Joint accelerations ddq (nv) for state (q, v) and joint forces tau (nv), in data.ddq, also
/// returned. Equal to M(q)^-1 (tau - C(q, v) v - g(q)).
///
/// With loops (Model::subsystems not empty), (q, v) must be consistent with the closures; each
/// sub-system's maps G, g are computed here (subsystem_maps.hpp) and the sub-system is one
/// aggregate body (subsystem_aba.hpp). tau then holds the forces of every tree joint (those on
/// dependent joints act through G^T); the result is the accelerations of every tree joint,
/// qdd_s = G ydd + g inside sub-systems, and ydd is in data.subsystem[s].ydd. Still O(n) overall.
/// forward_dynamics_loops (loop_forward_dynamics.hpp) adds the dead-point status.
template <typename S>
const VecX<S>& aba(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                   const ConstVecRef<S>& tau) {
  if (!model.subsystems.empty()) {
    subsystem_velocity_maps<S>(model, data, q);
    subsystem_acceleration_biases<S>(model, data, q, v);
  }
  return detail::aba_recursion<S>(model, data, q, v, tau);
}

}  // namespace mbgen
