#pragma once
// Derivatives of the actuators' forces f and the residual r (actuator_forces.hpp) with respect
// to the independent coordinates y (along the closed set), their rates yd and accelerations ydd:
// what a planner that optimises actuator effort through closed linkages linearises.
//
// f and r come from tau_y = T^T ID(q, T yd, T ydd + g), whose derivatives
// loop_dynamics_derivatives.hpp gives (dtau_y/dy, dtau_y/dyd, and M_y for ydd):
//  - an actuator that is an independent coordinate y_c takes tau_y's row c: df = dtau_y(c, :);
//  - a block of dependent actuators solves B f = tau_y's share (B(c, j) = d q_actuator_j / d y_c,
//    rows of the sub-system's G), so  B df = d(tau_y's share) - dB f, where dB, nonzero only
//    along the block's own independent coordinates, is made of the rows of dG the closure's map
//    derivatives already hold; the solve reuses the Givens factor of B that actuator_forces left;
//  - r keeps tau_y's rows no actuator reaches and is zero on the others, and so are its derivatives.
#include <vector>

#include "mbgen/algorithm/actuator_forces.hpp"
#include "mbgen/algorithm/loop_dynamics_derivatives.hpp"

namespace mbgen {

/// Results and work memory. Making it allocates; actuator_forces_derivatives does not.
template <typename S> struct ActuatorForceDerivatives {
  ActuatorForceDerivatives(const Model& model, const Actuation& act);
  VecX<S> f;                        ///< na: the actuators' forces (actuator_forces)
  VecX<S> residual;                 ///< ny: what no actuator supplies
  MatX<S> df_dy, df_dyd, df_dydd;  ///< na x ny
  MatX<S> dr_dy, dr_dyd, dr_dydd;  ///< ny x ny
  LoopDynamicsDerivatives<S> dynamics;  ///< tau_y's derivatives (and T, M_y) at the same state
  std::vector<MatX<S>> block_rhs;       ///< per block: p x ny
};

template <typename S>
ActuatorForceDerivatives<S>::ActuatorForceDerivatives(const Model& model, const Actuation& act) : dynamics(model) {
  const int na = act.num_actuators(), ny = model.structure().num_independent();
  f = VecX<S>::Zero(na);
  residual = VecX<S>::Zero(ny);
  df_dy = df_dyd = df_dydd = MatX<S>::Zero(na, ny);
  dr_dy = dr_dyd = dr_dydd = MatX<S>::Zero(ny, ny);
  for (const Actuation::Block& b : act.blocks)
    block_rhs.push_back(MatX<S>::Zero(static_cast<int>(model.subsystems[static_cast<std::size_t>(b.subsystem)].independent.size()), ny));
}

/// f, r and their derivatives with respect to y, yd and ydd (ny each) at the closed configuration
/// q. Singular where actuator_forces reports a block at its dead point or the closure is at one
/// (the results are then not to be used). No allocation.
template <typename S>
ClosureStatus actuator_forces_derivatives(const Model& model, Data<S>& data, const Actuation& act, ActuatorForceDerivatives<S>& out,
                                          const ConstVecRef<S>& q, const ConstVecRef<S>& yd, const ConstVecRef<S>& ydd) {
  const bool regular = actuator_forces<S>(model, data, act, q, yd, ydd, out.f, out.residual);
  // The blocks' factors stay in data.subsystem[k].actuator_*, which the derivatives do not touch.
  const ClosureStatus status = inverse_dynamics_loops_derivatives<S>(model, data, out.dynamics, q, yd, ydd);
  const LoopDynamicsDerivatives<S>& ld = out.dynamics;
  const ModelStructure& st = model.structure();
  out.dr_dy = ld.dtauy_dy;
  out.dr_dyd = ld.dtauy_dyd;
  out.dr_dydd = ld.M_y;
  for (std::size_t i = 0; i < act.actuated_v.size(); ++i) {
    const int c = act.direct_column[i];
    if (c < 0) continue;
    const int row = static_cast<int>(i);
    out.df_dy.row(row) = ld.dtauy_dy.row(c);
    out.df_dyd.row(row) = ld.dtauy_dyd.row(c);
    out.df_dydd.row(row) = ld.M_y.row(c);
    out.dr_dy.row(c).setZero();
    out.dr_dyd.row(c).setZero();
    out.dr_dydd.row(c).setZero();
  }
  for (std::size_t bi = 0; bi < act.blocks.size(); ++bi) {
    const Actuation::Block& b = act.blocks[bi];
    const std::size_t k = static_cast<std::size_t>(b.subsystem);
    const SubSystem& sub = model.subsystems[k];
    const SubSystemWork<S>& w = data.subsystem[k];
    const std::vector<int>& role = st.subsystems[k].coordinate_role;
    const int p = static_cast<int>(sub.independent.size());
    const auto column = [&](int c) { return st.column_of_v[static_cast<std::size_t>(sub.independent[static_cast<std::size_t>(c)])]; };
    MatX<S>& rhs = out.block_rhs[bi];
    for (int which = 0; which < 3; ++which) {
      const MatX<S>& dtau = which == 0 ? ld.dtauy_dy : which == 1 ? ld.dtauy_dyd : ld.M_y;
      MatX<S>& df = which == 0 ? out.df_dy : which == 1 ? out.df_dyd : out.df_dydd;
      for (int c = 0; c < p; ++c) rhs.row(c) = dtau.row(column(c));
      if (which == 0)  // - dB_d f along the block's own y_d: dB_d(c, j) = dG(actuator j, c)/dy_d
        for (int d = 0; d < p; ++d)
          for (int c = 0; c < p; ++c) {
            S x = S(0);
            for (int j = 0; j < p; ++j) {
              const int local = b.local[static_cast<std::size_t>(j)];
              if (role[static_cast<std::size_t>(local)] < 0) x += ld.dG[k](local, d * p + c) * out.f[b.actuators[static_cast<std::size_t>(j)]];
            }
            rhs(c, column(d)) -= x;
          }
      givens_qr_apply<S>(w.actuator_c, w.actuator_s, p, rhs, static_cast<int>(rhs.cols()));  // B^-1 = R^-1 Q^T
      upper_triangular_solve<S>(w.actuator_B, p, rhs, static_cast<int>(rhs.cols()));
      for (int j = 0; j < p; ++j) df.row(b.actuators[static_cast<std::size_t>(j)]) = rhs.row(j);
    }
    for (int c = 0; c < p; ++c) {
      out.dr_dy.row(column(c)).setZero();
      out.dr_dyd.row(column(c)).setZero();
      out.dr_dydd.row(column(c)).setZero();
    }
  }
  return regular && status == ClosureStatus::Converged ? ClosureStatus::Converged : ClosureStatus::Singular;
}

}  // namespace mbgen
