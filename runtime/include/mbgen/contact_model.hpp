#pragma once
// What the model says about ground contact (docs/simulation.md): the spheres of a robot that may
// touch the ground, the ground plane, and the parameters of the compliant law. Plain data of the
// model layer, so that the loader, the generator, the algorithms (algorithm/contact_points.hpp)
// and the simulator (sim/) all read one definition; the law itself is algorithm/contact_law.hpp.
#include <cmath>
#include <string>

#include "mbgen/index.hpp"
#include "mbgen/spatial/types.hpp"

namespace mbgen {

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

}  // namespace mbgen
