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
// of the ground): penetration delta = offset + r - n . c, witness w = c - r n (the sphere's
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

/// The law at one sphere. c, v_c, omega: centre, centre velocity and body angular velocity
/// (world). Writes the force at the witness into `force` and returns the report. Templated so
/// that an automatic-differentiation scalar gives the stiff integrator its exact Jacobian.
template <typename T>
ContactReport<T> contact_law(const Vec3<T>& c, const Vec3<T>& v_c, const Vec3<T>& omega, double radius,
                             const GroundPlane& ground, const ContactParameters& p) {
  using std::abs;
  using std::pow;
  using std::sqrt;
  ContactReport<T> out;
  const Vec3<T> n(T(ground.normal.x()), T(ground.normal.y()), T(ground.normal.z()));
  out.penetration = T(ground.offset + radius) - n.dot(c);
  out.point = c - T(radius) * n;
  if (!(out.penetration > T(0))) return out;
  out.active = true;
  const Vec3<T> v_w = v_c + omega.cross(-T(radius) * n);
  const T normal_rate = -n.dot(v_w);
  out.slip_velocity = v_w - n * n.dot(v_w);
  // delta^1.5 (Hertz) as delta sqrt(delta): a square root costs a fraction of a pow.
  const T spring = T(p.stiffness) * (p.exponent == 1.5 ? T(out.penetration * sqrt(out.penetration))
                                                       : static_cast<T>(pow(out.penetration, p.exponent)));
  T fn = spring * (T(1) + T(p.damping) * normal_rate);
  if (fn < T(0)) fn = T(0);
  out.normal_force = fn;
  // sqrt only above the stiction velocity: at zero slip its derivative would be 0/0.
  const T slip_squared = out.slip_velocity.squaredNorm();
  const T scale = slip_squared > T(p.stiction_velocity * p.stiction_velocity) ? T(sqrt(slip_squared)) : T(p.stiction_velocity);
  out.force = fn * n - (T(p.friction) * fn / scale) * out.slip_velocity;
  return out;
}

/// Elastic energy stored in a contact at penetration delta: k delta^(e+1) / (e+1) (the spring
/// part of the law; the damping and friction only dissipate).
template <typename S> S contact_spring_energy(S delta, const ContactParameters& p) {
  using std::pow;
  return delta > S(0) ? S(p.stiffness) * pow(delta, S(p.exponent + 1)) / S(p.exponent + 1) : S(0);
}

}  // namespace mbgen::sim
