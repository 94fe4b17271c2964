#pragma once
// Work memory of one sub-system (loop_closure.hpp) for the articulated-body algorithm with
// sub-systems (algorithm/subsystem_aba.hpp), sized once from the model: k coordinates, p
// independent coordinates, m bodies. Part of Data<S>.
#include <stdexcept>
#include <string>
#include <vector>

#include "mbgen/model.hpp"

namespace mbgen {

template <typename S> struct SubSystemWork {
  SubSystemWork() = default;
  /// Throws std::invalid_argument if the sub-system is not one aba() can treat: its bodies must
  /// be moved by 1-DoF joints (coordinates[j] the joint of bodies[j]), each body's parent must be
  /// in the sub-system or be its root. Drives may use either rotor model (subsystem_aba.hpp).
  SubSystemWork(const Model& model, const SubSystem& s)
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
    auto fail = [&](const std::string& what) {
      throw std::invalid_argument("sub-system of closure(s) rooted at body '" + model.body(s.root).name + "': " + what);
    };
    if (s.coordinates.size() != s.bodies.size()) fail("needs one coordinate per body");
    for (std::size_t j = 0; j < s.bodies.size(); ++j) {
      const Body& body = model.body(s.bodies[j]);
      const Joint& joint = model.joint(body.joint);
      if (joint.nv != 1 || joint.idx_v != s.coordinates[j])
        fail("body '" + body.name + "' must be moved by the 1-DoF joint of coordinate " + std::to_string(s.coordinates[j]));
      int parent = -1;
      for (std::size_t i = 0; i < j; ++i)
        if (s.bodies[i] == body.parent) parent = static_cast<int>(i);
      if (parent < 0 && body.parent != s.root)
        fail("body '" + body.name + "' hangs from '" + model.body(body.parent).name + "', which is neither in the sub-system nor its root");
      parent_local.push_back(parent);
      bool found = false;
      int role = 0;
      for (std::size_t c = 0; c < s.independent.size(); ++c)
        if (s.independent[c] == s.coordinates[j]) role = static_cast<int>(c), found = true;
      for (std::size_t d = 0; d < s.dependent.size(); ++d)
        if (s.dependent[d] == s.coordinates[j]) role = -1 - static_cast<int>(d), found = true;
      if (!found) fail("coordinate " + std::to_string(s.coordinates[j]) + " is neither independent nor dependent");
      coordinate_role.push_back(role);
    }
    // Leaves first: a body is rigid when every child is a rigid body of the sub-system whose
    // joint carries no rotor body (a rotor's inertia would join this body's).
    rigid.assign(s.bodies.size(), 1);
    for (std::size_t j = s.bodies.size(); j-- > 0;)
      for (const BodyIndex child : model.body(s.bodies[j]).children) {
        std::size_t c = 0;
        while (c < s.bodies.size() && s.bodies[c] != child) ++c;
        if (c == s.bodies.size() || model.joint(model.body(child).joint).has_rotor_body() || !rigid[c]) rigid[j] = 0;
      }
    moments.resize(s.bodies.size());
    if (!s.closures.empty() && static_cast<int>(s.dependent.size()) != s.rank())
      fail("has " + std::to_string(s.dependent.size()) + " dependent coordinates for " + std::to_string(s.rank()) +
           " independent constraint rows: Phi_z must be square");
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

  std::vector<int> parent_local;    ///< per body: its parent's position in bodies, or -1 (the root)
  /// Per body: 1 when nothing but rigid bodies of this sub-system hangs below it (no tree
  /// subtree, no other sub-system, no rotor body), so that its gathered inertia is a rigid body's
  /// and moves to the parent as mass moments (subsystem_backward).
  std::vector<char> rigid;
  std::vector<InertiaMoments<S>> moments;  ///< per rigid body: it and the rigid bodies below it, in its frame
  /// Per coordinate: its column among the independent coordinates (>= 0), or -1 - its row among
  /// the dependent ones.
  std::vector<int> coordinate_role;

 private:
  static int k(const SubSystem& s) { return static_cast<int>(s.coordinates.size()); }
  static int p(const SubSystem& s) { return static_cast<int>(s.independent.size()); }
  static int m(const SubSystem& s) { return static_cast<int>(s.bodies.size()); }
};

}  // namespace mbgen
