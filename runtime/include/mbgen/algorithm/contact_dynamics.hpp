#pragma once
// Forward dynamics under the ground's compliant contacts (sim/contact.hpp), in one pass of the
// articulated-body algorithm: the contact forces enter as external forces on the bodies that
// carry the spheres, between the velocity pass (which gives those bodies' velocities) and the
// force passes. The generator traces this into NAME::contact_accelerations, the simulator's step.
//
// Why body forces and not joint forces (tau += J^T f, contact_joint_forces): the joint-space form
// needs every contact body's chain of world-axes Jacobian columns, its twist summed along the
// chain and its wrench projected back along it, about 2000 operations on Lola's feet; as body
// forces the recursion's own velocities and the world poses the loops' Jacobian already computes
// serve, and the wrench is two rotations per body (the law itself, per sphere, is the same).
#include <vector>

#include "mbgen/algorithm/aba.hpp"
#include "mbgen/algorithm/contact_points.hpp"
#include "mbgen/algorithm/loop_forward_dynamics.hpp"

namespace mbgen {

/// Accelerations of every tree joint (data.ddq, nv) at (q, v) under joint forces tau (nv) and the
/// ground's forces on the spheres; writes kContactOutputs numbers per sphere to out. ground
/// and law as contact_inputs writes them, exponent the law's. With loops, q must be closed
/// and only the independent entries of v (ModelStructure::independent_v) are read: the dependent ones,
/// for the dynamics and the contacts alike, are T vy (as forward_dynamics_loops_independent).
template <typename S>
const VecX<S>& contact_forward_dynamics(const Model& model, Data<S>& data, const std::vector<ContactSphere>& spheres,
                                        double exponent, const ConstVecRef<S>& q, const ConstVecRef<S>& v,
                                        const ConstVecRef<S>& tau, const S* ground, const S* law, S* out) {
  if (model.subsystems.empty()) {
    forward_kinematics<S>(model, data, q);  // the world poses of the contact bodies
    detail::aba_velocity_pass<S>(model, data, q, v);
    subtract_contact_forces<S>(spheres, exponent, data, ground, law, out);
    return detail::aba_force_passes<S>(model, data, v, tau);
  }
  for (std::size_t i = 0; i < model.structure().independent_v.size(); ++i) data.scratch_y[static_cast<int>(i)] = v[model.structure().independent_v[i]];
  // The maps place only the loops' bodies; the contact forces need every body's world pose. The
  // full velocity is left in data.v_full.
  detail::loop_maps<S>(model, data, q, data.scratch_y);
  forward_kinematics<S>(model, data, q);
  detail::aba_velocity_pass<S>(model, data, q, data.v_full);
  subtract_contact_forces<S>(spheres, exponent, data, ground, law, out);
  return detail::aba_force_passes<S>(model, data, data.v_full, tau);
}

}  // namespace mbgen
