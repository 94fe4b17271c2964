#pragma once
// Compliant ground contact (docs/simulation.md): the robot's contact spheres against a plane.
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
#include <string>
#include <vector>

#include "mbgen/index.hpp"
#include "mbgen/spatial/types.hpp"

namespace mbgen::sim {

/// A sphere fixed in a body that may touch the ground: a vertex of one of its SSVs.
struct ContactSphere {
  BodyIndex body;
  Vec3<double> center = Vec3<double>::Zero();  ///< in the body frame, m
  double radius = 0;                           ///< m
  std::string name;                            ///< "<body>/<ssv index>/<vertex>", for reports
};

/// The ground: the half-space n . x <= offset (n unit, world frame).
struct GroundPlane {
  Vec3<double> normal = Vec3<double>::UnitZ();
  double offset = 0;  ///< m
  /// A plane through the origin tilted by `angle` (rad) about the world x axis: what a slope
  /// scenario needs.
  static GroundPlane tilted_about_x(double angle) {
    GroundPlane g;
    g.normal = Vec3<double>(0, -std::sin(angle), std::cos(angle));
    return g;
  }
};

/// Parameters of the compliant law (the extras' `scene: contact`, docs/extras.md).
struct ContactParameters {
  double stiffness = 2e7;           ///< k, N / m^exponent
  double damping = 2.0;             ///< d, Hunt-Crossley damping, s/m
  double exponent = 1.5;            ///< e: 1.5 is Hertz's sphere on a plane
  double friction = 0.8;            ///< mu, Coulomb coefficient
  double stiction_velocity = 1e-3;  ///< v_s, m/s
};

/// One contact's state and force after a step (the simulator reports one per sphere).
template <typename S> struct ContactReport {
  S penetration = S(0);                 ///< delta, m (<= 0 when apart)
  Vec3<S> point = Vec3<S>::Zero();      ///< witness w, world
  Vec3<S> force = Vec3<S>::Zero();      ///< on the robot at w, world, N
  Vec3<S> slip_velocity = Vec3<S>::Zero();  ///< tangential velocity of w, world, m/s
  S normal_force = S(0);                ///< f_n, N
  bool active = false;                  ///< delta > 0
};

/// The run-time inputs of the law as the backends' accelerations_with_contact (and the
/// generated contact_accelerations) read them: ground = {n_x, n_y, n_z, offset} and
/// law = {stiffness, damping, friction, stiction velocity}. The exponent is not among them: it
/// shapes the code (delta sqrt(delta) for 1.5), so a generated backend is specialised for its
/// scene's, and a runtime backend is given one at construction.
inline constexpr int kGroundInputs = 4, kLawInputs = 4;
inline void contact_inputs(const GroundPlane& g, const ContactParameters& p, double ground[kGroundInputs], double law[kLawInputs]) {
  ground[0] = g.normal.x(), ground[1] = g.normal.y(), ground[2] = g.normal.z(), ground[3] = g.offset;
  law[0] = p.stiffness, law[1] = p.damping, law[2] = p.friction, law[3] = p.stiction_velocity;
}

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

/// The law at one sphere: centre c, its velocity v_c and the body's angular velocity omega
/// (world); the witness is w = c - r n, moving at v_c + omega x (-r n).
template <typename T>
ContactForce<T> contact_force(const Vec3<T>& c, const Vec3<T>& v_c, const Vec3<T>& omega, double radius, const T* ground,
                              const T* law, double exponent) {
  const Vec3<T> n(ground[0], ground[1], ground[2]);
  const Vec3<T> to_witness = -T(radius) * n;
  return contact_force_at_witness<T>(c + to_witness, v_c + omega.cross(to_witness), ground, law, exponent);
}

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

/// Elastic energy stored in a contact at penetration delta: k delta^(e+1) / (e+1) (the spring
/// part of the law; the damping and friction only dissipate).
template <typename S> S contact_spring_energy(S delta, const ContactParameters& p) {
  using std::pow;
  return delta > S(0) ? S(p.stiffness) * pow(delta, S(p.exponent + 1)) / S(p.exponent + 1) : S(0);
}

}  // namespace mbgen::sim
