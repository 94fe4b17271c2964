#pragma once
// Centroidal momentum matrix (Orin and Goswami): h_G = A_G(q) v, the linear momentum and the
// angular momentum about the centre of mass, both in world axes.
#include "mbgen/algorithm/jacobian.hpp"
#include "mbgen/algorithm/center_of_mass.hpp"

namespace mbgen {

/// A_G (6 x nv) in data.Ag, also returned; sets data.com, data.mass and data.J. O(n): the bodies'
/// mass moments about the world origin (InertiaMoments: 10 numbers, they add without division)
/// are summed leaves to root into composites, and column c of A_G is the momentum of the
/// composite supported by joint c moving with the world joint column J_c, shifted to the CoM.
template <typename S> const Mat6X<S>& centroidal_momentum_matrix(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  compute_joint_jacobians<S>(model, data, q);
  data.mass = S(0);
  Vec3<S> first_moment = Vec3<S>::Zero();
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    data.composite[i] = InertiaMoments<S>::of(model.body(i).inertia, data.X_WB[i]);
    data.mass += data.composite[i].mass;
    first_moment += data.composite[i].first_moment;
  }
  data.com = first_moment / data.mass;
  for (int k = model.num_bodies() - 1; k >= 1; --k) {
    const BodyIndex i(k);
    const BodyIndex parent = model.body(i).parent;
    if (parent != kWorldBody) data.composite[parent] += data.composite[i];
  }
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex i(k);
    const Joint& joint = model.joint(model.body(i).joint);
    for (int col = 0; col < joint.nv; ++col) {
      const int c = joint.idx_v + col;
      const Force<S> h_O = data.composite[i] * Motion<S>::from_vector(data.J.col(c));
      data.Ag.col(c).template head<3>() = h_O.linear;
      data.Ag.col(c).template tail<3>() = h_O.angular - data.com.cross(h_O.linear);
    }
  }
  return data.Ag;
}

/// Centroidal momentum h_G = A_G v in data.hg (also fills data.Ag), returned.
template <typename S>
const Vec6<S>& centroidal_momentum(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  centroidal_momentum_matrix<S>(model, data, q);
  data.hg = data.Ag * v;
  return data.hg;
}

}  // namespace mbgen
