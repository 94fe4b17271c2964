#pragma once
// Velocity and acceleration maps of each sub-system, computed locally (DESIGN.md, "Kinematic
// loops and sub-systems"): with the sub-system's kept closure rows Phi_s and its coordinates split
// into independent y and dependent z,
//   qd_s = G yd,         G = [I; -Phi_z^-1 Phi_y]     (rows in SubSystem::coordinates order)
//   qdd_s = G ydd + g,   g = [0; Phi_z^-1 gamma]      (gamma = -(d/dt Phi_q) qd)
// Phi_z is factored by Givens rotations (givens_qr.hpp): branch-free, so the generator traces
// this very code, and stable without pivoting. The results go to Data::subsystem, where the
// articulated-body algorithm with sub-systems reads them (subsystem_aba.hpp).
#include <cmath>
#include <type_traits>

#include "mbgen/algorithm/closure.hpp"
#include "mbgen/algorithm/givens_qr.hpp"
#include "mbgen/algorithm/loop_maps.hpp"

namespace mbgen {

/// Smallest / largest |diagonal of R| of Phi_z over all sub-systems after
/// subsystem_velocity_maps (1 for a model without loops): how far from a dead point the
/// linkages are. NaN (from a 0 / 0 rotation) counts as singular.
template <typename S> S subsystem_pivot_ratio(const Model& model, const Data<S>& data) {
  using std::abs;
  S worst = S(1);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const MatX<S>& R = data.subsystem[k].R;
    S smallest = S(0), largest = S(0);
    for (int i = 0; i < R.rows(); ++i) {
      const S p = abs(R(i, i));
      if (i == 0 || !(p >= smallest)) smallest = p;
      if (p > largest) largest = p;
    }
    if (R.rows() > 0) {
      const S ratio = smallest / largest;
      if (!(ratio >= worst)) worst = ratio;
    }
  }
  return worst;
}

/// G of every sub-system at configuration q (nq), in data.subsystem[s].G; keeps Phi_z's factor
/// for subsystem_acceleration_biases at the same q. Needs no velocity.
template <typename S> void subsystem_velocity_maps(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  closure_jacobian<S>(model, data, q);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    SubSystemWork<S>& w = data.subsystem[k];
    const int r = sub.rank(), p = static_cast<int>(sub.independent.size());
    for (int i = 0; i < r; ++i) {
      const int row = sub.rows[static_cast<std::size_t>(i)];
      for (int c = 0; c < r; ++c) w.R(i, c) = data.Phi_q(row, sub.dependent[static_cast<std::size_t>(c)]);
      for (int c = 0; c < p; ++c) w.rhs(i, c) = data.Phi_q(row, sub.independent[static_cast<std::size_t>(c)]);
    }
    givens_qr_factor<S>(w.R, r, w.rotation_c, w.rotation_s);
    givens_qr_apply<S>(w.rotation_c, w.rotation_s, r, w.rhs, p);
    upper_triangular_solve<S>(w.R, r, w.rhs, p);
    for (std::size_t j = 0; j < sub.coordinates.size(); ++j) {
      const int role = w.coordinate_role[j];
      for (int c = 0; c < p; ++c) w.G(static_cast<int>(j), c) = role >= 0 ? S(role == c ? 1 : 0) : -w.rhs(-1 - role, c);
    }
  }
}

/// g of every sub-system at (q, v), v consistent (qd_s = G yd), in data.subsystem[s].g. Needs
/// subsystem_velocity_maps at the same q first.
template <typename S>
void subsystem_acceleration_biases(const Model& model, Data<S>& data, const ConstVecRef<S>& q, const ConstVecRef<S>& v) {
  closure_bias<S>(model, data, q, v);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    SubSystemWork<S>& w = data.subsystem[k];
    const int r = sub.rank(), p = static_cast<int>(sub.independent.size());
    for (int i = 0; i < r; ++i) w.rhs(i, p) = data.gamma[sub.rows[static_cast<std::size_t>(i)]];
    auto column = w.rhs.middleCols(p, 1);
    givens_qr_apply<S>(w.rotation_c, w.rotation_s, r, column, 1);
    upper_triangular_solve<S>(w.R, r, column, 1);
    for (std::size_t j = 0; j < sub.coordinates.size(); ++j) {
      const int role = w.coordinate_role[j];
      w.g[static_cast<int>(j)] = role >= 0 ? S(0) : w.rhs(-1 - role, p);
    }
  }
}

}  // namespace mbgen
