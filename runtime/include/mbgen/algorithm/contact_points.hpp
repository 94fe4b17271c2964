#pragma once
// Where the contact spheres are and how they move (sim/contact.hpp): the input of the ground
// contact, generic here and traced by the generator into NAME::contact_points.
#include <vector>

#include "mbgen/algorithm/jacobian.hpp"
#include "mbgen/sim/contact.hpp"

namespace mbgen {

/// For each sphere k: its centre in the world (positions[3k..3k+2]) and the 6 x nv Jacobian of
/// its body at the centre, rows [linear velocity of the centre; angular velocity], world axes
/// (LocalWorldAligned), row-major at jacobians[6 nv k]. The generic twin of the generated
/// contact_points.
template <typename S>
void contact_points(const Model& model, Data<S>& data, const std::vector<sim::ContactSphere>& spheres,
                    const ConstVecRef<S>& q, S* positions, S* jacobians) {
  compute_joint_jacobians<S>(model, data, q);
  const int nv = model.nv();
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    const sim::ContactSphere& s = spheres[k];
    const Vec3<S> c = data.X_WB[s.body].act(cast<S>(s.center));
    for (int i = 0; i < 3; ++i) positions[3 * k + static_cast<std::size_t>(i)] = c[i];
    // The columns of the joints that carry the body: data.J holds them in world axes at the
    // world origin; moved to the centre, linear += angular x c. The others stay zero.
    S* out = jacobians + 6 * nv * k;
    for (int i = 0; i < 6 * nv; ++i) out[i] = S(0);
    for (BodyIndex j = s.body; j != kWorldBody; j = model.body(j).parent) {
      const Joint& joint = model.joint(model.body(j).joint);
      for (int col = 0; col < joint.nv; ++col) {
        const int v = joint.idx_v + col;
        const Vec3<S> angular = data.J.col(v).template tail<3>();
        const Vec3<S> linear = data.J.col(v).template head<3>() + angular.cross(c);
        for (int r = 0; r < 3; ++r) {
          out[r * nv + v] = linear[r];
          out[(3 + r) * nv + v] = angular[r];
        }
      }
    }
  }
}

}  // namespace mbgen
