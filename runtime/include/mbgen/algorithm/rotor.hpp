#pragma once
// Geared rotors (harmonic drives, ball screws) of 1-DoF joints, in two fidelities (DESIGN.md):
//  - armature: the reflected inertia N^2 I_r on the diagonal of M (Joint::armature);
//  - body: a rotor R fixed in the parent body P that spins about the joint axis (a line through
//    the joint frame origin, direction w in P) at N times the joint rate. Only its axial inertia
//    I_r is modelled: its mass and transverse inertia are part of the parent link as the
//    description gives it, and being axisymmetric it looks the same to P at every spin angle.
//    Then R's spatial inertia in P is the constant [0 0; 0 I_r w w^T], its angular velocity is
//    w_R = w_P + N qd w, and the terms it adds are:
//      M:     N^2 I_r on the diagonal, N I_r w^T (angular columns of P's support) off it,
//             and I_r w w^T to P's composite inertia;
//      bias:  the gyroscopic moment I_r (w.w_R) (w_P x w) on P (dominant term N qd I_r w_P x w).
//    The rotor force F_R = [0; I_r (w.a_R) w + I_r (w.w_R)(w_P x w)] acts on P, and the joint
//    feels N w . F_R = N I_r (w.alpha_P + N qdd). These are the rotor terms of the
//    rotor-aware RNEA/CRBA/ABA of Featherstone's geared-motor model.
#include "mbgen/model.hpp"

namespace mbgen {

/// Spin axis of the joint's rotor, a unit vector in the parent body frame.
inline Vec3<double> rotor_axis_in_parent(const Joint& joint) { return joint.X_PJ.rotation * joint.axis; }

/// Spatial force the rotor of `joint` needs (in the parent frame P), given P's velocity and
/// acceleration (in P) and the joint's rate and acceleration. Only the body model has one.
template <typename S>
Force<S> rotor_force(const Joint& joint, const Motion<S>& v_P, const Motion<S>& a_P, const S& qd, const S& qdd) {
  const Vec3<S> w = rotor_axis_in_parent(joint).template cast<S>();
  const S N(joint.rotor_gear_ratio), I(joint.rotor_inertia);
  const S spin_acc = w.dot(a_P.angular) + N * qdd;  // w . alpha_R (w . (w_P x w) = 0)
  const S spin_rate = w.dot(v_P.angular) + N * qd;  // w . w_R
  return Force<S>{Vec3<S>::Zero(), w * (I * spin_acc) + v_P.angular.cross(w) * (I * spin_rate)};
}

/// Joint force the drive adds to tau: N w . F_R (body model) plus armature * qdd.
template <typename S> S rotor_joint_force(const Joint& joint, const Motion<S>& a_P, const S& qdd) {
  S f = S(joint.armature) * qdd;
  if (joint.has_rotor_body()) {
    const Vec3<S> w = rotor_axis_in_parent(joint).template cast<S>();
    const S N(joint.rotor_gear_ratio), I(joint.rotor_inertia);
    f += N * I * (w.dot(a_P.angular) + N * qdd);
  }
  return f;
}

/// The rotational part of the rotor's inertia about its spin axis, I_r w w^T, in the parent frame
/// (the rotor's mass and its inertia across the axis are part of the parent body).
template <typename S> Mat3<S> rotor_spin_inertia_in_parent(const Joint& joint) {
  const Vec3<double> w = rotor_axis_in_parent(joint);
  return (joint.rotor_inertia * w * w.transpose()).cast<S>();
}

/// The rotor's spatial inertia in the parent frame, [0 0; 0 I_r w w^T] (6x6).
template <typename S> Mat6<S> rotor_inertia_in_parent(const Joint& joint) {
  Mat6<S> I = Mat6<S>::Zero();
  I.template bottomRightCorner<3, 3>() = rotor_spin_inertia_in_parent<S>(joint);
  return I;
}

/// I_R S_R: the force on the rotor per unit of its own spin rate, [0; I_r w] in the parent frame.
template <typename S> Force<S> rotor_momentum_per_rate(const Joint& joint) {
  return Force<S>{Vec3<S>::Zero(), (joint.rotor_inertia * rotor_axis_in_parent(joint)).template cast<S>()};
}

/// Diagonal inertia the drive adds to its joint: armature + N^2 I_r.
inline double drive_diagonal_inertia(const Joint& joint) {
  return joint.armature + (joint.has_rotor_body() ? joint.rotor_gear_ratio * joint.rotor_gear_ratio * joint.rotor_inertia : 0.0);
}

/// Kinetic energy of the drive: 1/2 armature qd^2 + 1/2 I_r (w . w_R)^2.
template <typename S> S rotor_kinetic_energy(const Joint& joint, const Motion<S>& v_P, const S& qd) {
  S e = S(joint.armature) * qd * qd;
  if (joint.has_rotor_body()) {
    const S spin_rate = rotor_axis_in_parent(joint).template cast<S>().dot(v_P.angular) + S(joint.rotor_gear_ratio) * qd;
    e += S(joint.rotor_inertia) * spin_rate * spin_rate;
  }
  return e / S(2);
}

}  // namespace mbgen
