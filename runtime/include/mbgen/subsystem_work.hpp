#pragma once
// Work memory of one sub-system (loop_closure.hpp) for the articulated-body algorithm with
// sub-systems (algorithm/subsystem_aba.hpp), sized once from the model: k coordinates, p
// independent coordinates, m bodies. Part of Data<S>; the sub-system's layout is the Model's
// (ModelStructure::subsystems).
#include <stdexcept>
#include <string>
#include <vector>

#include "mbgen/model.hpp"

namespace mbgen {

template <typename S> struct SubSystemWork {
  SubSystemWork() = default;
  /// Sized for `s`; the Model has checked that aba() can treat it (Model::update_structure) and
  /// holds its layout (ModelStructure::subsystems).
  SubSystemWork(const Model&, const SubSystem& s)
      : G(MatX<S>::Zero(k(s), p(s))),
        g(VecX<S>::Zero(k(s))),
        H(MatX<S>::Zero(6 * m(s), p(s))),
        F(MatX<S>::Zero(6 * m(s), p(s))),
        bias(MatX<S>::Zero(6, m(s))),
        U(MatX<S>::Zero(6, p(s))),
        UDinv(MatX<S>::Zero(6, p(s))),
        D(MatX<S>::Zero(p(s), p(s))),
        D_factor(D),
        u(VecX<S>::Zero(p(s))),
        ydd(u),
        scratch(u),
        R(MatX<S>::Zero(s.rank(), s.rank())),
        rhs(MatX<S>::Zero(s.rank(), p(s) + 1)),
        rotation_c(VecX<S>::Zero(s.rank() * (s.rank() - 1) / 2 + 1)),
        rotation_s(rotation_c),
        actuator_B(MatX<S>::Zero(p(s), p(s))),
        actuator_rhs(VecX<S>::Zero(p(s))),
        actuator_f(VecX<S>::Zero(p(s))),
        actuator_c(VecX<S>::Zero(p(s) * (p(s) - 1) / 2 + 1)),
        actuator_s(actuator_c) {
    moments.resize(s.bodies.size());
  }

  /// Inputs of a step, set by the closure maps for the current state: the coordinates' rates are
  /// qd_s = G yd and their accelerations qdd_s = G ydd + g (rows in SubSystem::coordinates order,
  /// columns in SubSystem::independent order).
  MatX<S> G;
  VecX<S> g;

  MatX<S> H;         ///< 6m x p: acceleration of each body per unit ydd, body frame (rows 6j .. 6j+5)
  MatX<S> F;         ///< 6m x p: IA_b H_b, then gathered leaves to root
  MatX<S> bias;      ///< 6 x m: each body's acceleration at ydd = 0 with the root at rest, body frame
  MatX<S> U;         ///< 6 x p: sum over bodies of X^T IA H, in the root frame
  MatX<S> UDinv;     ///< 6 x p: U D^-1
  MatX<S> D;         ///< p x p: sum over bodies of H^T IA H (+ drive inertias G^T diag(armature) G)
  MatX<S> D_factor;  ///< LDL^T factor of D (small_ldlt.hpp)
  VecX<S> u;         ///< p: independent forces G^T tau_s minus the bias forces' share
  VecX<S> ydd;       ///< p: accelerations of the independent coordinates (result)
  VecX<S> scratch;   ///< p

  // The maps G, g from the closures (subsystem_maps.hpp): Phi_z = Q R by Givens rotations.
  MatX<S> R;           ///< rank x rank: Phi_z, then its R factor
  MatX<S> rhs;         ///< rank x (p + 1): [Phi_y | gamma], then Phi_z^-1 [Phi_y | gamma]
  VecX<S> rotation_c;  ///< the Givens rotations of Phi_z's factorisation (cosines, sines)
  VecX<S> rotation_s;

  // Actuator forces through a dependent actuator (algorithm/actuator_forces.hpp): B f = tau_y's
  // share, B = Q R by Givens rotations.
  MatX<S> actuator_B;  ///< p x p: d q_actuator / d y, then its R factor
  VecX<S> actuator_rhs, actuator_f;
  VecX<S> actuator_c, actuator_s;

  /// Per rigid body of the layout (SubSystemLayout::rigid): it and the rigid bodies below it, in
  /// its frame.
  std::vector<InertiaMoments<S>> moments;

 private:
  static int k(const SubSystem& s) { return static_cast<int>(s.coordinates.size()); }
  static int p(const SubSystem& s) { return static_cast<int>(s.independent.size()); }
  static int m(const SubSystem& s) { return static_cast<int>(s.bodies.size()); }
};

}  // namespace mbgen
