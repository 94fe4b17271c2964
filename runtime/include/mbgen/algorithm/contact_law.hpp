#pragma once
// The compliant ground-contact law (docs/simulation.md): the robot's contact spheres
// (contact_model.hpp) against a plane.
//
// Contact spheres. A point-SSV is one sphere; a line-SSV's distance to a plane is smallest at
// one of its two end spheres and a triangle-SSV's at one of its three corner spheres (the
// distance to a plane is linear along the core), so the spheres at the cores' vertices give each
// SSV's exact penetration and witness point. Keeping every vertex as its own contact, rather than
// the lowest one only, is what lets a flat foot stand: a capsule lying on the ground touches it
// along its whole segment, and one witness point jumping between its ends would make the foot
// rock and chatter; the vertex spheres share the load as a distributed support does.
//
// The law, per sphere (centre c, radius r; plane n . x = offset, n the unit normal pointing out
// of the ground; contact_force): penetration delta = offset + r - n . c, witness w = c - r n (the sphere's
// lowest point), its velocity v_w = v_c + omega x (-r n), normal rate delta_dot = -n . v_w.
//   normal:  f_n = k delta^e (1 + d delta_dot), clamped at 0 (Hunt and Crossley 1975): the
//            damping grows with the penetration, so the force is continuous at touch-down and
//            never pulls;
//   tangent: f_t = -mu f_n v_t / max(|v_t|, v_s), regularised Coulomb friction: viscous below
//            the stiction velocity v_s, Coulomb above (a block sliding faster than v_s
//            decelerates at exactly mu g).
// The force acts at w; on the body it is f at the centre c and the moment (w - c) x f.
#include <cmath>

#include "mbgen/contact_model.hpp"

namespace mbgen {

/// What the law gives at one sphere; accelerations_with_contact writes these kContactOutputs
/// numbers per sphere, in this order.
template <typename T> struct ContactForce {
  T penetration = T(0);                     ///< delta, m (<= 0 when apart)
  Vec3<T> point = Vec3<T>::Zero();          ///< witness w, world
  Vec3<T> force = Vec3<T>::Zero();          ///< on the robot at w, world, N (0 when apart)
  Vec3<T> slip_velocity = Vec3<T>::Zero();  ///< tangential velocity of w, world, m/s
};
inline constexpr int kContactOutputs = 10;

/// The larger of a and b, both converted to T first (an automatic-differentiation expression
/// would make std::max and Eigen's overload ambiguous; the symbolic scalar's is found by ADL).
template <typename T> T contact_max(const T& a, const T& b) {
  using std::max;
  return max(a, b);
}

/// 1 where x > 0, else 0 (also at x = 0): the slope of max(x, 0), as the select max compiles to
/// picks 0 there. The symbolic scalar has its own (found by argument-dependent lookup), which the
/// generator prints as a select too.
template <typename T> T unit_step(const T& x) { return x > T(0) ? T(1) : T(0); }

/// delta^e for delta >= 0: a product or a square root for the usual exponents (a square root
/// costs a fraction of a pow), pow otherwise.
template <typename T> T contact_spring_power(const T& delta, double exponent) {
  using std::pow;
  using std::sqrt;
  if (exponent == 1) return delta;
  if (exponent == 1.5) return delta * sqrt(delta);
  if (exponent == 2) return delta * delta;
  return pow(delta, exponent);
}

/// d(delta^e)/d delta for delta >= 0 and e >= 1 (the extras refuse e < 1): finite at 0, where it
/// is 0 but for e = 1.
template <typename T> T contact_spring_slope(const T& delta, double exponent) {
  using std::pow;
  using std::sqrt;
  if (exponent == 1) return T(1);
  if (exponent == 1.5) return T(1.5) * sqrt(delta);
  if (exponent == 2) return T(2) * delta;
  return T(exponent) * pow(delta, T(exponent - 1));
}

/// The law at a witness point w (the sphere's lowest point, world) moving at v_w, without a branch
/// on the state (max and sqrt only, so that the generator traces it into the generated
/// contact_accelerations; apart, every force term is exactly 0). ground and law as contact_inputs
/// writes them. Templated so that an automatic-differentiation scalar gives the stiff integrator
/// its exact Jacobian (where delta > 0).
template <typename T>
ContactForce<T> contact_force_at_witness(const Vec3<T>& w, const Vec3<T>& v_w, const T* ground, const T* law, double exponent) {
  using std::sqrt;
  ContactForce<T> out;
  const Vec3<T> n(ground[0], ground[1], ground[2]);
  out.penetration = ground[3] - n.dot(w);  // = offset + r - n . c
  out.point = w;
  const T normal_velocity = n.dot(v_w);
  out.slip_velocity = v_w - n * normal_velocity;
  const T spring = law[0] * contact_spring_power<T>(contact_max<T>(out.penetration, T(0)), exponent);
  const T fn = contact_max<T>(spring * (T(1) - law[1] * normal_velocity), T(0));
  // max(|v_t|, v_s) as the root of the larger square: at zero slip the root's argument is v_s^2,
  // never 0, so its derivative stays finite.
  const T scale = sqrt(contact_max<T>(out.slip_velocity.squaredNorm(), law[3] * law[3]));
  out.force = fn * n - (law[2] * fn / scale) * out.slip_velocity;
  return out;
}

/// The law's force f at w moving at v_w (contact_force_at_witness's) and its Jacobians df/dw and
/// df/dv_w (world axes, 3 x 3), by hand and without a branch on the state, so that the generator
/// traces them into the generated contact derivatives. With pen the penetration, h = k delta^e
/// (1 - d n . v_w) the unclamped normal force, s = slip, sigma = sqrt(max(|s|^2, v_s^2)),
/// P = I - n n^T:
///   f = f_n u,  u = n - mu s / sigma,  f_n = max(h, 0),  delta = max(pen, 0),  d pen = -n . dw,
///   df_n = [h > 0] ((1 - d n . v_w) k e delta^(e-1) [pen > 0] d pen - k delta^e d n . dv_w),
///   ds = P dv_w,  d sigma = [|s|^2 > v_s^2] (P s) . dv_w / sigma,
///   df/dw = u df_n/dw,  df/dv_w = u df_n/dv_w - (mu f_n / sigma) (P - [|s|^2 > v_s^2] s (P s)^T / sigma^2).
/// Where a max switches (touch-down, the clamp, the stiction speed), the slope of the side its
/// select takes: 0 at a tie. Apart, every entry is exactly 0.
template <typename T>
void contact_force_jacobians(const Vec3<T>& w, const Vec3<T>& v_w, const T* ground, const T* law, double exponent, Vec3<T>& f,
                             Mat3<T>& df_dw, Mat3<T>& df_dv) {
  using std::sqrt;
  const Vec3<T> n(ground[0], ground[1], ground[2]);
  const T penetration = ground[3] - n.dot(w);
  const T delta = contact_max<T>(penetration, T(0));
  const T normal_velocity = n.dot(v_w);
  const Vec3<T> slip = v_w - n * normal_velocity;
  const T spring = law[0] * contact_spring_power<T>(delta, exponent);
  const T damping_factor = T(1) - law[1] * normal_velocity;
  const T h = spring * damping_factor;
  const T fn = contact_max<T>(h, T(0));
  const T stiction2 = law[3] * law[3];
  const T slip2 = slip.squaredNorm();
  const T sigma = sqrt(contact_max<T>(slip2, stiction2));
  const T mu_over_sigma = law[2] / sigma;
  const Vec3<T> u = n - mu_over_sigma * slip;
  f = fn * u;
  const T pressing = unit_step(h);
  const T dfn_dpen = pressing * damping_factor * law[0] * contact_spring_slope<T>(delta, exponent) * unit_step(penetration);
  df_dw = u * (-dfn_dpen * n).transpose();
  const Mat3<T> P = Mat3<T>::Identity() - n * n.transpose();
  const Vec3<T> Ps = P * slip;
  const T sliding = unit_step(slip2 - stiction2) / (sigma * sigma);
  df_dv = u * (-(pressing * spring * law[1]) * n).transpose() - (mu_over_sigma * fn) * (P - sliding * slip * Ps.transpose());
}

/// The law at one sphere: centre c, its velocity v_c and the body's angular velocity omega
/// (world); the witness is w = c - r n, moving at v_c + omega x (-r n).
template <typename T>
ContactForce<T> contact_force(const Vec3<T>& c, const Vec3<T>& v_c, const Vec3<T>& omega, double radius, const T* ground,
                              const T* law, double exponent) {
  const Vec3<T> n(ground[0], ground[1], ground[2]);
  const Vec3<T> to_witness = -T(radius) * n;
  return contact_force_at_witness<T>(c + to_witness, v_c + omega.cross(to_witness), ground, law, exponent);
}

/// Elastic energy stored in a contact at penetration delta: k delta^(e+1) / (e+1) (the spring
/// part of the law; the damping and friction only dissipate).
template <typename S> S contact_spring_energy(S delta, const ContactParameters& p) {
  using std::pow;
  return delta > S(0) ? S(p.stiffness) * pow(delta, S(p.exponent + 1)) / S(p.exponent + 1) : S(0);
}

}  // namespace mbgen
