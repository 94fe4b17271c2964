#pragma once
// Where the contact spheres are and how they move, and the joint forces the ground exerts through
// them (sim/contact.hpp): generic here, traced by the generator into NAME::contact_points and
// (with the loop recursion after it) NAME::contact_accelerations.
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

/// The ground's joint forces, added to tau (nv): for each sphere the law (sim::contact_force) at
/// its centre, moving with the velocities v (nv, every tree joint's), and J^T of its force at the
/// witness. Writes sim::kContactOutputs numbers per sphere to `out` (penetration, witness,
/// force, slip velocity). ground and law as sim::contact_inputs writes them. No Jacobian is
/// stored: the spheres of one body (consecutive in `spheres`, as contact_spheres lists them) add
/// their wrench about the world origin, and one pass down the body's chain maps it to its joints:
/// tau_i += J_i^T [f; w x f], J_i the joint's world-axes column at the origin.
template <typename S>
void contact_joint_forces(const Model& model, Data<S>& data, const std::vector<sim::ContactSphere>& spheres, double exponent,
                          const ConstVecRef<S>& q, const S* v, const S* ground, const S* law, S* tau, S* out) {
  compute_joint_jacobians<S>(model, data, q);
  const auto chain_twist = [&](BodyIndex body, Vec3<S>& linear, Vec3<S>& angular) {
    linear.setZero(), angular.setZero();
    for (BodyIndex j = body; j != kWorldBody; j = model.body(j).parent) {
      const Joint& joint = model.joint(model.body(j).joint);
      for (int col = 0; col < joint.nv; ++col) {
        const int i = joint.idx_v + col;
        linear += data.J.col(i).template head<3>() * v[i];
        angular += data.J.col(i).template tail<3>() * v[i];
      }
    }
  };
  std::size_t k = 0;
  while (k < spheres.size()) {
    const BodyIndex body = spheres[k].body;
    Vec3<S> linear, omega, force = Vec3<S>::Zero(), moment = Vec3<S>::Zero();
    chain_twist(body, linear, omega);
    for (; k < spheres.size() && spheres[k].body == body; ++k) {
      const Vec3<S> c = data.X_WB[body].act(cast<S>(spheres[k].center));
      const Vec3<S> v_c = linear + omega.cross(c);
      const sim::ContactForce<S> f = sim::contact_force<S>(c, v_c, omega, spheres[k].radius, ground, law, exponent);
      S* o = out + sim::kContactOutputs * k;
      o[0] = f.penetration;
      for (int r = 0; r < 3; ++r) o[1 + r] = f.point[r], o[4 + r] = f.force[r], o[7 + r] = f.slip_velocity[r];
      force += f.force;
      moment += f.point.cross(f.force);
    }
    for (BodyIndex j = body; j != kWorldBody; j = model.body(j).parent) {
      const Joint& joint = model.joint(model.body(j).joint);
      for (int col = 0; col < joint.nv; ++col) {
        const int i = joint.idx_v + col;
        tau[i] += data.J.col(i).template head<3>().dot(force) + data.J.col(i).template tail<3>().dot(moment);
      }
    }
  }
}

}  // namespace mbgen
