#pragma once
// Composite-rigid-body algorithm: the joint-space mass matrix M(q).
#include "mbgen/algorithm/kinematics.hpp"
#include "mbgen/algorithm/rotor.hpp"

namespace mbgen {

/// Mass matrix (nv x nv, symmetric, both triangles filled) in data.M, also returned. Composite
/// inertias are kept as mass moments (10 numbers, InertiaMoments) in each body's frame: they move
/// to the parent with a rotation and a parallel-axis shift and add entry by entry, where the 6x6
/// form costs a 6x6 congruence per body and, traced, does not even see that its mass block stays m 1.
template <typename S> const MatX<S>& crba(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    const Joint& joint = model.joint(model.body(i).joint);
    data.X_J[i] = joint_motion_transform<S>(joint, q.data() + joint.idx_q);
    data.Y[i] = InertiaMoments<S>::of_body(model.body(i).inertia);
    // A rotor body moves with its parent except for its own spin (rotor.hpp).
    const BodyIndex parent = model.body(i).parent;
    if (joint.has_rotor_body() && parent != kWorldBody) data.Y[parent].rotational += rotor_spin_inertia_in_parent<S>(joint);
  }
  for (int k = model.num_bodies() - 1; k >= 1; --k) {
    const BodyIndex i(k);
    const Body& body = model.body(i);
    const Joint& ji = model.joint(body.joint);
    for (int col = 0; col < ji.nv; ++col) {
      // Force needed to move the composite body i with unit velocity of this joint column,
      // carried down the support chain and projected on each ancestor joint.
      Force<S> F = data.Y[i] * joint_subspace_column<S>(ji, col);
      const int c = ji.idx_v + col;
      BodyIndex j = i;
      while (j != kWorldBody) {
        const Joint& jj = model.joint(model.body(j).joint);
        S proj[6];
        joint_project<S>(jj, F, proj);
        for (int r = 0; r < jj.nv; ++r) {
          data.M(jj.idx_v + r, c) = proj[r];
          data.M(c, jj.idx_v + r) = proj[r];
        }
        if (j == i && col == 0 && (ji.armature != 0 || ji.has_rotor_body())) {
          data.M(c, c) += S(drive_diagonal_inertia(ji));
        }
        const BodyIndex parent = model.body(j).parent;
        if (parent != kWorldBody) {
          F = force_child_to_parent<S>(jj, data.X_J[j], F);
          // This joint's rate also spins its rotor, which pushes on the parent.
          if (j == i && ji.has_rotor_body()) F += rotor_momentum_per_rate<S>(ji) * S(ji.rotor_gear_ratio);
        }
        j = parent;
      }
    }
    if (body.parent != kWorldBody) data.Y[body.parent] += moments_child_to_parent<S>(ji, data.X_J[i], data.Y[i]);
  }
  return data.M;
}

}  // namespace mbgen
