#pragma once
// Where the contact spheres are and how they move, and the forces the ground exerts through them
// (sim/contact.hpp): as body forces for the articulated-body algorithm (contact_dynamics.hpp,
// traced by the generator into NAME::contact_accelerations) or as joint forces for the
// joint-space backends; generic here, and traced into NAME::contact_points.
#include <vector>

#include "mbgen/algorithm/jacobian.hpp"
#include "mbgen/algorithm/contact_law.hpp"

namespace mbgen {

/// For each sphere k: its centre in the world (positions[3k..3k+2]) and the 6 x nv Jacobian of
/// its body at the centre, rows [linear velocity of the centre; angular velocity], world axes
/// (LocalWorldAligned), row-major at jacobians[6 nv k]. The generic twin of the generated
/// contact_points.
template <typename S>
void contact_points(const Model& model, Data<S>& data, const std::vector<ContactSphere>& spheres,
                    const ConstVecRef<S>& q, S* positions, S* jacobians) {
  compute_joint_jacobians<S>(model, data, q);
  const int nv = model.nv();
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    const ContactSphere& s = spheres[k];
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

namespace detail {
/// The law (contact_force) at the spheres of one body: spheres[k] and the ones after it on
/// the same body (contact_spheres lists a body's spheres together). X_WB: the body's pose;
/// v_origin, omega: the velocity of its origin and its angular velocity, world axes. Writes
/// kContactOutputs numbers per sphere to out, adds their force (world) to `force` and their
/// moment about the body's origin (world axes) to `moment`, and returns the index after them.
template <typename S>
std::size_t body_ground_wrench(const std::vector<ContactSphere>& spheres, std::size_t k, double exponent, const SE3<S>& X_WB,
                               const Vec3<S>& v_origin, const Vec3<S>& omega, const S* ground, const S* law, S* out,
                               Vec3<S>& force, Vec3<S>& moment) {
  const BodyIndex body = spheres[k].body;
  const Vec3<S> n(ground[0], ground[1], ground[2]);
  for (; k < spheres.size() && spheres[k].body == body; ++k) {
    // origin to witness (the sphere's lowest point w = c - r n), world axes
    const Vec3<S> r = X_WB.rotation * cast<S>(spheres[k].center) - S(spheres[k].radius) * n;
    const ContactForce<S> f =
        contact_force_at_witness<S>(X_WB.translation + r, v_origin + omega.cross(r), ground, law, exponent);
    S* o = out + kContactOutputs * k;
    o[0] = f.penetration;
    for (int i = 0; i < 3; ++i) o[1 + i] = f.point[i], o[4 + i] = f.force[i], o[7 + i] = f.slip_velocity[i];
    force += f.force;
    moment += r.cross(f.force);
  }
  return k;
}
}  // namespace detail

/// The ground's forces on the bodies as external forces of the articulated-body algorithm: for
/// each body with spheres, the law at its spheres (body_ground_wrench) moving with the body
/// velocities data.v (body frame), its wrench about the body origin in body axes subtracted from
/// the bias force data.pA. Needs data.X_WB (world poses) and aba_velocity_pass's data.v and
/// data.pA at the same state; run between aba_velocity_pass and aba_force_passes
/// (contact_dynamics.hpp). Writes kContactOutputs numbers per sphere to out.
template <typename S>
void subtract_contact_forces(const std::vector<ContactSphere>& spheres, double exponent, Data<S>& data, const S* ground,
                             const S* law, S* out) {
  std::size_t k = 0;
  while (k < spheres.size()) {
    const BodyIndex body = spheres[k].body;
    const Mat3<S>& R = data.X_WB[body].rotation;
    Vec3<S> force = Vec3<S>::Zero(), moment = Vec3<S>::Zero();
    k = detail::body_ground_wrench<S>(spheres, k, exponent, data.X_WB[body], R * data.v[body].linear, R * data.v[body].angular,
                                      ground, law, out, force, moment);
    data.pA[body].linear -= R.transpose() * force;
    data.pA[body].angular -= R.transpose() * moment;
  }
}

/// The ground's joint forces, added to tau (nv): for each sphere the law (contact_force) at
/// its centre, moving with the velocities v (nv, every tree joint's), and J^T of its force at the
/// witness. Writes kContactOutputs numbers per sphere to `out` (penetration, witness,
/// force, slip velocity). ground and law as contact_inputs writes them. What the
/// joint-space backends (KKT, independent coordinates) add to their forces; the articulated-body
/// one takes the same law as body forces (subtract_contact_forces). No Jacobian is stored: the
/// spheres of one body add their wrench about the world origin, and one pass down the body's
/// chain maps it to its joints: tau_i += J_i^T [f; m], J_i the joint's world-axes column at the
/// origin.
template <typename S>
void contact_joint_forces(const Model& model, Data<S>& data, const std::vector<ContactSphere>& spheres, double exponent,
                          const ConstVecRef<S>& q, const S* v, const S* ground, const S* law, S* tau, S* out) {
  compute_joint_jacobians<S>(model, data, q);
  std::size_t k = 0;
  while (k < spheres.size()) {
    const BodyIndex body = spheres[k].body;
    // The body's twist at the world origin, world axes: the sum of its chain's columns.
    Vec3<S> linear = Vec3<S>::Zero(), omega = Vec3<S>::Zero(), force = Vec3<S>::Zero(), moment = Vec3<S>::Zero();
    for (BodyIndex j = body; j != kWorldBody; j = model.body(j).parent) {
      const Joint& joint = model.joint(model.body(j).joint);
      for (int col = 0; col < joint.nv; ++col) {
        const int i = joint.idx_v + col;
        linear += data.J.col(i).template head<3>() * v[i];
        omega += data.J.col(i).template tail<3>() * v[i];
      }
    }
    const Vec3<S>& p = data.X_WB[body].translation;
    k = detail::body_ground_wrench<S>(spheres, k, exponent, data.X_WB[body], linear + omega.cross(p), omega, ground, law, out,
                                      force, moment);
    moment += p.cross(force);  // about the world origin
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
