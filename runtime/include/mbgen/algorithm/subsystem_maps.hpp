#pragma once
// Velocity and acceleration maps of each sub-system, computed locally (DESIGN.md, "Kinematic
// loops and sub-systems"): with the sub-system's kept closure rows Phi_s and its coordinates split
// into independent y and dependent z,
//   qd_s = G yd,         G = [I; -Phi_z^-1 Phi_y]     (rows in SubSystem::coordinates order)
//   qdd_s = G ydd + g,   g = [0; Phi_z^-1 gamma]      (gamma = -(d/dt Phi_q) qd)
// Phi_z is factored by Givens rotations (givens_qr.hpp): branch-free, so the generator traces
// this very code, and stable without pivoting. The results go to Data::subsystem, where the
// articulated-body algorithm with sub-systems reads them (subsystem_aba.hpp). The maps of the
// whole system (velocity_map, full_velocities, acceleration_bias) assemble them: T is the
// identity off the loops and each sub-system's G on its coordinates.
#include <cmath>
#include <type_traits>

#include "mbgen/algorithm/closure.hpp"
#include "mbgen/algorithm/givens_qr.hpp"

namespace mbgen {

namespace detail {
/// Smallest / largest |R_ii| of sub-system k's factor (1 for an empty sub-system); NaN (from a
/// 0 / 0 rotation) stays NaN.
template <typename S> S pivot_ratio_of(const Data<S>& data, std::size_t k) {
  using std::abs;
  const MatX<S>& R = data.subsystem[k].R;
  S smallest = S(0), largest = S(0);
  for (int i = 0; i < R.rows(); ++i) {
    const S p = abs(R(i, i));
    if (i == 0 || !(p >= smallest)) smallest = p;
    if (p > largest) largest = p;
  }
  return R.rows() > 0 ? smallest / largest : S(1);
}
}  // namespace detail

/// Smallest / largest |diagonal of R| of Phi_z over all sub-systems after
/// subsystem_velocity_maps (1 for a model without loops): how far from a dead point the
/// linkages are. NaN (from a 0 / 0 rotation) counts as singular.
template <typename S> S subsystem_pivot_ratio(const Model& model, const Data<S>& data) {
  S worst = S(1);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const S ratio = detail::pivot_ratio_of<S>(data, k);
    if (!(ratio >= worst)) worst = ratio;
  }
  return worst;
}

/// The smallest over sub-systems of their pivot ratio divided by SubSystem::nominal_pivot_ratio
/// (the ratio at the assembled pose): a scale-free distance from a dead point, 1 at the
/// assembled pose and without loops (closure_positions' dead-point test). NaN counts as singular.
template <typename S> S subsystem_relative_pivot_ratio(const Model& model, const Data<S>& data) {
  S worst = S(1);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const S relative = detail::pivot_ratio_of<S>(data, k) / S(model.subsystems[k].nominal_pivot_ratio);
    if (!(relative >= worst)) worst = relative;
  }
  return worst;
}

namespace detail {
/// Copies sub-system k's Phi_z (its kept rows, its dependent columns) from data.Phi_q into
/// data.subsystem[k].R, ready for givens_qr_factor.
template <typename S> void load_dependent_block(const Model& model, Data<S>& data, std::size_t k) {
  const SubSystem& sub = model.subsystems[k];
  MatX<S>& R = data.subsystem[k].R;
  for (int i = 0; i < sub.rank(); ++i)
    for (int c = 0; c < sub.rank(); ++c)
      R(i, c) = data.Phi_q(sub.rows[static_cast<std::size_t>(i)], sub.dependent[static_cast<std::size_t>(c)]);
}

/// Phi_z^-1 times sub-system k's kept entries of `rows` (all closure rows: data.Phi, data.gamma)
/// into the last column of data.subsystem[k].rhs, by the factor of Phi_z the sub-system holds.
template <typename S> void solve_kept_rows(const Model& model, Data<S>& data, std::size_t k, const VecX<S>& rows) {
  const SubSystem& sub = model.subsystems[k];
  SubSystemWork<S>& w = data.subsystem[k];
  const int r = sub.rank(), p = static_cast<int>(sub.independent.size());
  for (int i = 0; i < r; ++i) w.rhs(i, p) = rows[sub.rows[static_cast<std::size_t>(i)]];
  auto column = w.rhs.middleCols(p, 1);
  givens_qr_apply<S>(w.rotation_c, w.rotation_s, r, column, 1);
  upper_triangular_solve<S>(w.R, r, column, 1);
}
}  // namespace detail

/// G of every sub-system at configuration q (nq), in data.subsystem[s].G; keeps Phi_z's factor
/// for subsystem_acceleration_biases at the same q. Needs no velocity. Places only the loops'
/// bodies (closure.hpp, detail::cycle_placements): data's world poses are not q's.
template <typename S> void subsystem_velocity_maps(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  detail::cycle_placements<S>(model, data, q.data());
  detail::jacobian_from_placements<S>(model, data);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    SubSystemWork<S>& w = data.subsystem[k];
    const SubSystemLayout& layout = model.structure().subsystems[k];
    const int r = sub.rank(), p = static_cast<int>(sub.independent.size());
    detail::load_dependent_block<S>(model, data, k);
    for (int i = 0; i < r; ++i)
      for (int c = 0; c < p; ++c) w.rhs(i, c) = data.Phi_q(sub.rows[static_cast<std::size_t>(i)], sub.independent[static_cast<std::size_t>(c)]);
    givens_qr_factor<S>(w.R, r, w.rotation_c, w.rotation_s);
    givens_qr_apply<S>(w.rotation_c, w.rotation_s, r, w.rhs, p);
    upper_triangular_solve<S>(w.R, r, w.rhs, p);
    for (std::size_t j = 0; j < sub.coordinates.size(); ++j) {
      const int role = layout.coordinate_role[j];
      for (int c = 0; c < p; ++c) w.G(static_cast<int>(j), c) = role >= 0 ? S(role == c ? 1 : 0) : -w.rhs(-1 - role, c);
    }
  }
}

/// g of every sub-system at (q, v), v consistent (qd_s = G yd), in data.subsystem[s].g. Needs
/// subsystem_velocity_maps at the same q first: its factor, and its placements of the loops'
/// bodies, which this reads (q itself is not read again).
template <typename S>
void subsystem_acceleration_biases(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  (void)q;
  detail::bias_from_placements<S>(model, data, v.data());
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    SubSystemWork<S>& w = data.subsystem[k];
    const SubSystemLayout& layout = model.structure().subsystems[k];
    const int p = static_cast<int>(sub.independent.size());
    detail::solve_kept_rows<S>(model, data, k, data.gamma);
    for (std::size_t j = 0; j < sub.coordinates.size(); ++j) {
      const int role = layout.coordinate_role[j];
      w.g[static_cast<int>(j)] = role >= 0 ? S(0) : w.rhs(-1 - role, p);
    }
  }
}

namespace detail {
/// x_full = T x_y (+ g_full if with_bias), x_y in ModelStructure::independent_v order. Needs the
/// sub-systems' G (and g with the bias).
template <typename S, typename In, typename Out>
void expand_independent(const Model& model, const Data<S>& data, const In& x_y, bool with_bias, Out&& x_full) {
  for (std::size_t i = 0; i < model.structure().independent_v.size(); ++i) x_full[model.structure().independent_v[i]] = x_y[static_cast<int>(i)];
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    const SubSystemWork<S>& w = data.subsystem[k];
    const SubSystemLayout& layout = model.structure().subsystems[k];
    for (std::size_t j = 0; j < sub.coordinates.size(); ++j) {
      if (layout.coordinate_role[j] >= 0) continue;  // independent: set above (its g is 0)
      S x = with_bias ? w.g[static_cast<int>(j)] : S(0);
      for (std::size_t c = 0; c < sub.independent.size(); ++c) x += w.G(static_cast<int>(j), static_cast<int>(c)) * x_full[sub.independent[c]];
      x_full[sub.coordinates[j]] = x;
    }
  }
}
}  // namespace detail

/// Velocities of every tree joint, v = T vy (nv), from the independent ones vy (ny,
/// ModelStructure::independent_v order) at a closed configuration q: the velocity that keeps the loops
/// closed (Phi_q v = 0). Computes the sub-systems' G.
template <typename S, typename Out>
void full_velocities(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& vy, Out&& v) {
  subsystem_velocity_maps<S>(model, data, q);
  detail::expand_independent<S>(model, data, vy, false, v);
}

namespace detail {
/// T (nv x ny) from the sub-systems' G already at q (velocity_map without computing them).
template <typename S, typename Out> void velocity_map_from_maps(const Model& model, const Data<S>& data, Out&& T) {
  T.setZero();
  for (std::size_t i = 0; i < model.structure().independent_v.size(); ++i) T(model.structure().independent_v[i], static_cast<int>(i)) = S(1);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    const SubSystemWork<S>& w = data.subsystem[k];
    const SubSystemLayout& layout = model.structure().subsystems[k];
    for (std::size_t j = 0; j < sub.coordinates.size(); ++j) {
      if (layout.coordinate_role[j] >= 0) continue;
      for (std::size_t c = 0; c < sub.independent.size(); ++c)
        T(sub.coordinates[j], model.structure().column_of_v[static_cast<std::size_t>(sub.independent[c])]) = w.G(static_cast<int>(j), static_cast<int>(c));
    }
  }
}
}  // namespace detail

/// The velocity map T (nv x ny) at q: v = T vy for every velocity that keeps the loops closed.
/// Dense; controllers that only need T vy use full_velocities.
template <typename S, typename Out> void velocity_map(const Model& model, Data<S>& data, const ConstVecRef<S>& q, Out&& T) {
  subsystem_velocity_maps<S>(model, data, q);
  detail::velocity_map_from_maps<S>(model, data, T);
}

/// The acceleration bias g (nv) at (q, vy): qdd = T ydd + g keeps the loops closed; zero at the
/// independent coordinates. Computes the sub-systems' G and g (the full velocity in data.v_full).
template <typename S, typename Out>
void acceleration_bias(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& vy, Out&& g) {
  full_velocities<S>(model, data, q, vy, data.v_full);
  subsystem_acceleration_biases<S>(model, data, q, data.v_full);
  VecX<S>& zero_y = data.scratch_y;
  zero_y.setZero();
  detail::expand_independent<S>(model, data, zero_y, true, g);
}

}  // namespace mbgen
