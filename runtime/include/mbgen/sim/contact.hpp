#pragma once
// The ground contact as the simulator reports it: per sphere, the law of
// algorithm/contact_law.hpp with the scene's plane and parameters (contact_model.hpp).
#include "mbgen/algorithm/contact_law.hpp"

namespace mbgen::sim {

/// One contact's state and force after a step (the simulator reports one per sphere).
template <typename S> struct ContactReport {
  S penetration = S(0);                 ///< delta, m (<= 0 when apart)
  Vec3<S> point = Vec3<S>::Zero();      ///< witness w, world
  Vec3<S> force = Vec3<S>::Zero();      ///< on the robot at w, world, N
  Vec3<S> slip_velocity = Vec3<S>::Zero();  ///< tangential velocity of w, world, m/s
  S normal_force = S(0);                ///< f_n, N
  bool active = false;                  ///< delta > 0
};

/// The law at one sphere as the simulator reports it (contact_force with the parameters of
/// `ground` and `p`, the slip zeroed when apart).
template <typename T>
ContactReport<T> contact_law(const Vec3<T>& c, const Vec3<T>& v_c, const Vec3<T>& omega, double radius,
                             const GroundPlane& ground, const ContactParameters& p) {
  double g[kGroundInputs], l[kLawInputs];
  contact_inputs(ground, p, g, l);
  const T gt[kGroundInputs] = {T(g[0]), T(g[1]), T(g[2]), T(g[3])}, lt[kLawInputs] = {T(l[0]), T(l[1]), T(l[2]), T(l[3])};
  const ContactForce<T> f = contact_force<T>(c, v_c, omega, radius, gt, lt, p.exponent);
  ContactReport<T> out;
  out.penetration = f.penetration;
  out.point = f.point;
  out.active = f.penetration > T(0);
  if (!out.active) return out;
  out.force = f.force;
  out.slip_velocity = f.slip_velocity;
  out.normal_force = f.force.dot(Vec3<T>(gt[0], gt[1], gt[2]));
  return out;
}

}  // namespace mbgen::sim
