#pragma once
// Data<S>: work memory of the algorithms for scalar S. Making it allocates; after that no
// algorithm allocates (tests/test_no_allocation.cpp proves it with a malloc guard). What depends
// on the model alone (index tables, the sub-systems' layouts) is the Model's: model.structure().
#include "mbgen/subsystem_work.hpp"

namespace mbgen {

template <typename S> struct Data {
  explicit Data(const Model& model)
      : X_J(model.num_bodies()),
        X_PB(model.num_bodies()),
        X_WB(model.num_bodies()),
        X_WF(model.num_frames()),
        X_TB(model.num_bodies()),
        v_T(model.num_bodies()),
        a_T(model.num_bodies()),
        v(model.num_bodies()),
        a(model.num_bodies()),
        c(model.num_bodies()),
        f(model.num_bodies()),
        Y(model.num_bodies()),
        composite(model.num_bodies()),
        IA(model.num_bodies(), Mat6<S>::Zero()),
        pA(model.num_bodies()),
        U(model.num_bodies(), Mat6<S>::Zero()),
        D_inv(model.num_bodies(), Mat6<S>::Zero()),
        u(model.num_bodies(), Vec6<S>::Zero()),
        tau(VecX<S>::Zero(model.nv())),
        ddq(VecX<S>::Zero(model.nv())),
        M(MatX<S>::Zero(model.nv(), model.nv())),
        J(Mat6X<S>::Zero(6, model.nv())),
        Ag(Mat6X<S>::Zero(6, model.nv())),
        Jcom(Mat3X<S>::Zero(3, model.nv())),
        Phi(VecX<S>::Zero(model.num_constraint_rows())),
        Phi_q(MatX<S>::Zero(model.num_constraint_rows(), model.nv())),
        gamma(VecX<S>::Zero(model.num_constraint_rows())),
        zero_v(VecX<S>::Zero(model.nv())),
        v_full(VecX<S>::Zero(model.nv())) {
    // The algorithms read the model's structure; one left behind by a change of its loops (or of
    // a rotor in a loop) would index this workspace wrongly.
    if (!model.structure_is_current())
      throw std::logic_error("Data: model '" + model.name +
                             "' changed after its structure was computed: call model.update_structure() after changing its "
                             "closures, sub-systems or joints");
    for (const SubSystem& s : model.subsystems) subsystem.emplace_back(model, s);
    const int ny = model.structure().num_independent();
    tau_y = VecX<S>::Zero(ny);
    scratch_y = VecX<S>::Zero(ny);
    scratch_nv = VecX<S>::Zero(model.nv());
    M_y = MatX<S>::Zero(ny, ny);
  }

  IndexedVector<BodyIndex, SE3<S>> X_J;    ///< joint transform: pose of each body in its joint frame
  IndexedVector<BodyIndex, SE3<S>> X_PB;   ///< pose of each body in its parent
  IndexedVector<BodyIndex, SE3<S>> X_WB;   ///< pose of each body in the world
  IndexedVector<FrameIndex, SE3<S>> X_WF;  ///< pose of each frame in the world
  /// A loop's cycle relative to its top body T (the common ancestor of the closure's two bodies,
  /// taken at rest): pose in T, velocity and acceleration at zero joint accelerations (body
  /// frame) of each body on the cycle (algorithm/closure.hpp). Valid for the last closure computed.
  IndexedVector<BodyIndex, SE3<S>> X_TB;
  IndexedVector<BodyIndex, Motion<S>> v_T;
  IndexedVector<BodyIndex, Motion<S>> a_T;
  IndexedVector<BodyIndex, Motion<S>> v;   ///< body spatial velocity, body frame
  IndexedVector<BodyIndex, Motion<S>> a;   ///< body spatial acceleration (incl. -gravity), body frame
  IndexedVector<BodyIndex, Motion<S>> c;   ///< velocity-product acceleration v x (S v_j), body frame
  IndexedVector<BodyIndex, Force<S>> f;    ///< net force transmitted by each joint, body frame
  IndexedVector<BodyIndex, InertiaMoments<S>> Y;  ///< composite inertia (CRBA) as mass moments about the body's origin, body frame
  IndexedVector<BodyIndex, InertiaMoments<S>> composite;  ///< composite mass moments about the body's origin, body frame (centroidal)
  IndexedVector<BodyIndex, Mat6<S>> IA;    ///< articulated-body inertia, body frame
  IndexedVector<BodyIndex, Force<S>> pA;   ///< articulated bias force, body frame
  IndexedVector<BodyIndex, Mat6<S>> U;     ///< IA * S (first nv columns used)
  IndexedVector<BodyIndex, Mat6<S>> D_inv; ///< 1/(S^T IA S) for 1-DoF joints; its LDL^T factor (small_ldlt.hpp) otherwise
  IndexedVector<BodyIndex, Vec6<S>> u;     ///< tau - S^T pA (first nv entries used)

  VecX<S> tau;     ///< joint forces (RNEA output)
  VecX<S> ddq;     ///< joint accelerations (ABA output)
  MatX<S> M;       ///< joint-space mass matrix (CRBA output, both triangles)
  Mat6X<S> J;      ///< joint Jacobian columns in the world frame (at the world origin)
  Mat6X<S> Ag;     ///< centroidal momentum matrix, [linear; angular about the CoM], world axes
  Vec6<S> hg = Vec6<S>::Zero();  ///< centroidal momentum Ag v
  S mass = S(0);                 ///< total mass
  Vec3<S> com = Vec3<S>::Zero();   ///< centre of mass, world
  Vec3<S> vcom = Vec3<S>::Zero();  ///< velocity of the centre of mass, world
  Mat3X<S> Jcom;                   ///< centre-of-mass Jacobian, world

  // Loop closures (algorithm/closure.hpp); m = model.num_constraint_rows(), 0 for a tree.
  VecX<S> Phi;     ///< stacked closure residual (m)
  MatX<S> Phi_q;   ///< constraint Jacobian (m x nv), velocity coordinates
  VecX<S> gamma;   ///< bias with Phi_q qdd = gamma (m)
  VecX<S> zero_v;  ///< nv zeros: the joint accelerations of the velocity-product pass
  VecX<S> v_full;  ///< nv: every tree joint's velocity, built from independent ones (loop_forward_dynamics.hpp)

  std::vector<SubSystemWork<S>> subsystem;          ///< one per Model::subsystems entry (aba with loops)
  VecX<S> tau_y;                 ///< ny: forces on the independent coordinates (inverse_dynamics_loops)
  MatX<S> M_y;                   ///< ny x ny: mass matrix in independent coordinates (mass_matrix_loops)
  VecX<S> scratch_y, scratch_nv;
};

}  // namespace mbgen
