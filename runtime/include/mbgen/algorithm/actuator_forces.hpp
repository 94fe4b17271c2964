#pragma once
// Closed-system inverse dynamics for the actuators: the forces the actuated joints must apply
// for given independent accelerations, with the loops closed and the dependent joints passive.
//
// With the independent coordinates y (ModelStructure::independent_v) and the velocity map T (v = T vy),
// the generalized forces on y are (loop_inverse_dynamics.hpp)
//   tau_y = T^T RNEA(q, T vy, T ydd + g).
// Actuator forces f (na, one per actuated coordinate, S_a its columns of the identity) reach y as
// T^T S_a f, so they must solve  T^T S_a f = tau_y - r,  r the part no actuator can supply:
//  - an actuated coordinate that is independent has its row of T equal to e_y: f_a = tau_y[y];
//  - an actuated coordinate that is dependent (a slider driving a slider-crank through its
//    crank) acts on its sub-system's independent coordinates through its row of G; such a
//    sub-system must have as many actuators as independent coordinates (a square block B_s,
//    B_s(c, j) = G(actuator j, c)), solved by Givens QR. At a dead point of the actuator
//    (B_s singular) the force is unbounded: the result is not finite, and the generic version
//    reports it;
//  - an independent coordinate no actuator reaches (the floating base, an idle spin, a joint left
//    out of the actuated set) keeps its tau_y in r: what contacts or other external forces must
//    supply. r is zero on every coordinate the actuators span.
// So forward dynamics with joint forces S_a f + S_y r (r placed at the independent coordinates)
// returns ydd: the check tests/test_actuator_forces.cpp makes.
//
// The generated NAME::actuator_forces is this function traced (the generator's symbolic scalar),
// for the actuated set of the description (actuated_joint_names in the generated header).
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "mbgen/algorithm/givens_qr.hpp"
#include "mbgen/algorithm/loop_inverse_dynamics.hpp"

namespace mbgen {

/// Which coordinates carry actuators, and how their forces reach the independent coordinates.
/// Built once from the model (make_actuation); the computation does not allocate.
struct Actuation {
  std::vector<int> actuated_v;  ///< na: v index of each actuated coordinate, the order of f
  /// Per actuated coordinate, its column in y when it is independent and reaches it directly
  /// (row e_y of T), else -1 (it is in a block).
  std::vector<int> direct_column;
  /// A sub-system where some actuator is a dependent coordinate: the actuators (indices into
  /// actuated_v, as many as the sub-system's independent coordinates) and, per actuator, its
  /// place among the sub-system's coordinates.
  struct Block {
    int subsystem = 0;
    std::vector<int> actuators;
    std::vector<int> local;
  };
  std::vector<Block> blocks;
  int num_actuators() const { return static_cast<int>(actuated_v.size()); }
};

namespace detail {
/// Per v index, its column among the independent coordinates, or -1 if a loop makes it dependent.
inline std::vector<int> independent_columns(const Model& model) {
  std::vector<int> column(static_cast<std::size_t>(model.nv()), 0);
  for (const SubSystem& s : model.subsystems)
    for (int z : s.dependent) column[static_cast<std::size_t>(z)] = -1;
  int ny = 0;
  for (int& c : column)
    if (c == 0) c = ny++;
  return column;
}
}  // namespace detail

/// The independent coordinates of the model except a floating base: the actuated set when a
/// description names none.
inline std::vector<int> default_actuated_v(const Model& model) {
  std::vector<int> out;
  const std::vector<int> column = detail::independent_columns(model);
  for (int i = model.floating_base() ? 6 : 0; i < model.nv(); ++i)
    if (column[static_cast<std::size_t>(i)] >= 0) out.push_back(i);
  return out;
}

/// Throws std::invalid_argument naming the coordinate or the sub-system: an index out of range
/// or repeated, a floating-base coordinate, a sub-system with a dependent actuator and not as
/// many actuators as independent coordinates.
inline Actuation make_actuation(const Model& model, const std::vector<int>& actuated_v) {
  Actuation a;
  a.actuated_v = actuated_v;
  const int base = model.floating_base() ? 6 : 0;
  const std::vector<int> column = detail::independent_columns(model);
  std::vector<int> subsystem_of(static_cast<std::size_t>(model.nv()), -1);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k)
    for (int c : model.subsystems[k].coordinates) subsystem_of[static_cast<std::size_t>(c)] = static_cast<int>(k);
  std::vector<bool> seen(static_cast<std::size_t>(model.nv()), false);
  for (int v : actuated_v) {
    if (v < 0 || v >= model.nv()) throw std::invalid_argument("actuation: coordinate " + std::to_string(v) + " is not one of model '" + model.name + "''s " + std::to_string(model.nv()) + " velocity coordinates");
    if (v < base) throw std::invalid_argument("actuation: coordinate " + std::to_string(v) + " belongs to the floating base of '" + model.name + "', which no joint actuator moves");
    if (seen[static_cast<std::size_t>(v)]) throw std::invalid_argument("actuation: coordinate " + std::to_string(v) + " is listed twice");
    seen[static_cast<std::size_t>(v)] = true;
  }
  a.direct_column.assign(actuated_v.size(), -1);
  // Sub-systems with a dependent actuator become blocks; every other actuator is direct.
  std::vector<int> block_of(model.subsystems.size(), -1);
  for (std::size_t i = 0; i < actuated_v.size(); ++i) {
    const int v = actuated_v[i];
    if (column[static_cast<std::size_t>(v)] < 0) {
      const int k = subsystem_of[static_cast<std::size_t>(v)];
      if (block_of[static_cast<std::size_t>(k)] < 0) {
        block_of[static_cast<std::size_t>(k)] = static_cast<int>(a.blocks.size());
        a.blocks.push_back({k, {}, {}});
      }
    }
  }
  for (std::size_t i = 0; i < actuated_v.size(); ++i) {
    const int v = actuated_v[i];
    const int k = subsystem_of[static_cast<std::size_t>(v)];
    if (k >= 0 && block_of[static_cast<std::size_t>(k)] >= 0) {
      Actuation::Block& b = a.blocks[static_cast<std::size_t>(block_of[static_cast<std::size_t>(k)])];
      const SubSystem& s = model.subsystems[static_cast<std::size_t>(k)];
      b.actuators.push_back(static_cast<int>(i));
      for (std::size_t j = 0; j < s.coordinates.size(); ++j)
        if (s.coordinates[j] == v) b.local.push_back(static_cast<int>(j));
    } else {
      a.direct_column[i] = column[static_cast<std::size_t>(v)];
    }
  }
  for (const Actuation::Block& b : a.blocks) {
    const SubSystem& s = model.subsystems[static_cast<std::size_t>(b.subsystem)];
    if (b.actuators.size() != s.independent.size()) {
      std::string closures;
      for (int c : s.closures) closures += (closures.empty() ? "" : ", ") + model.closures[static_cast<std::size_t>(c)].name;
      throw std::invalid_argument("actuation: the loops of " + closures + " have " + std::to_string(s.independent.size()) +
                                  " independent coordinate(s) and " + std::to_string(b.actuators.size()) +
                                  " actuator(s), some of them dependent: with a dependent actuator, a sub-system needs exactly as "
                                  "many actuators as independent coordinates (actuate the independent joints instead, or add the missing actuators)");
    }
  }
  return a;
}

/// The actuators' forces f (na) and the residual r (ny) that no actuator can supply, for the
/// independent accelerations ydd at (q, vy) (see the top of this file). Returns false when a
/// block of dependent actuators is singular to round-off (a dead point: f is huge or not finite).
template <typename S, typename OutF, typename OutR>
bool actuator_forces(const Model& model, Data<S>& data, const Actuation& act, const ConstVecRef<S>& q, const ConstVecRef<S>& vy,
                     const ConstVecRef<S>& ydd, OutF&& f, OutR&& residual) {
  const VecX<S>& tau_y = inverse_dynamics_independent<S>(model, data, q, vy, ydd);
  for (int i = 0; i < tau_y.size(); ++i) residual[i] = tau_y[i];
  for (std::size_t i = 0; i < act.actuated_v.size(); ++i) {
    const int c = act.direct_column[i];
    if (c < 0) continue;
    f[static_cast<int>(i)] = tau_y[c];
    residual[c] = S(0);
  }
  bool regular = true;
  for (const Actuation::Block& b : act.blocks) {
    const SubSystem& sub = model.subsystems[static_cast<std::size_t>(b.subsystem)];
    SubSystemWork<S>& w = data.subsystem[static_cast<std::size_t>(b.subsystem)];
    const SubSystemLayout& layout = model.structure().subsystems[static_cast<std::size_t>(b.subsystem)];
    const int p = static_cast<int>(sub.independent.size());
    // B (c, j) = d q_actuator_j / d y_c: G's row for a dependent actuator, e_c for an independent one.
    MatX<S>& B = w.actuator_B;
    for (int j = 0; j < p; ++j) {
      const int local = b.local[static_cast<std::size_t>(j)];
      const int role = layout.coordinate_role[static_cast<std::size_t>(local)];
      for (int c = 0; c < p; ++c) B(c, j) = role >= 0 ? S(role == c ? 1 : 0) : w.G(local, c);
    }
    for (int c = 0; c < p; ++c) {
      const int col = model.structure().column_of_v[static_cast<std::size_t>(sub.independent[static_cast<std::size_t>(c)])];
      w.actuator_rhs[c] = tau_y[col];
      residual[col] = S(0);
    }
    S scale = S(1);  // the pivots' reference (generic only: the regularity check below)
    if constexpr (std::is_floating_point_v<S>) scale = std::max(S(1), B.cwiseAbs().maxCoeff());
    givens_qr_factor<S>(B, p, w.actuator_c, w.actuator_s);
    givens_qr_apply<S>(w.actuator_c, w.actuator_s, p, w.actuator_rhs, 1);
    for (int r = p - 1; r >= 0; --r) {  // back substitution: R f = Q^T rhs
      S x = w.actuator_rhs[r];
      for (int c = r + 1; c < p; ++c) x -= B(r, c) * w.actuator_f[c];
      w.actuator_f[r] = x / B(r, r);
    }
    for (int j = 0; j < p; ++j) f[b.actuators[static_cast<std::size_t>(j)]] = w.actuator_f[j];
    // Singular to round-off (a pivot within 16 units of round-off of B's scale) or not finite.
    if constexpr (std::is_floating_point_v<S>)
      for (int j = 0; j < p; ++j)
        regular = regular && std::isfinite(w.actuator_f[j]) && std::abs(B(j, j)) > S(16) * std::numeric_limits<S>::epsilon() * scale;
  }
  return regular;
}

}  // namespace mbgen
