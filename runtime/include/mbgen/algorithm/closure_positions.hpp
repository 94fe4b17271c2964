#pragma once
// Position level of the closed system (DESIGN.md, "Kinematic loops and sub-systems"): Newton on
// Phi_s(y, z) = 0 for the dependent coordinates z of every sub-system, y held, warm-started from
// the z in q. Each step factors the sub-system's own Phi_z by Givens rotations (givens_qr.hpp),
// the factorisation the velocity and acceleration maps use (subsystem_maps.hpp): one
// implementation for the three levels, stable without pivoting, and branch-free, so the generator
// traces the step (detail::closure_newton_step) and emits the loop around it.
//
// Status, never a silent NaN: a fixed loop with an iteration cap that reports Converged,
// NotConverged (cap reached, a non-finite residual, or a non-finite coordinate off the loops) or Singular: a linkage at its dead point,
// where z is not a function of y. Singular is found two ways: Phi_z's smallest |R_ii| below
// singular_tolerance times its largest, along the way or at the solution (no Newton step can be
// trusted there); or a converged pose that the residual tolerance cannot tell from a dead point,
// its pivot ratio below dead_point_tolerance times the sub-system's ratio at the assembled pose
// (what float needs: see dead_point_tolerance). q is left at the last finite iterate. No
// allocation.
#include <cmath>
#include <limits>
#include <type_traits>

#include "mbgen/algorithm/closure.hpp"
#include "mbgen/algorithm/givens_qr.hpp"
#include "mbgen/algorithm/subsystem_maps.hpp"

namespace mbgen {

enum class ClosureStatus { Converged, NotConverged, Singular };

inline const char* to_string(ClosureStatus s) {
  switch (s) {
    case ClosureStatus::Converged: return "converged";
    case ClosureStatus::NotConverged: return "not_converged";
    case ClosureStatus::Singular: return "singular";
  }
  return "unknown";
}

struct ClosureOptions {
  double tolerance = 1e-12;  ///< max |Phi| over the kept rows (m and rad)
  int max_iterations = 20;
  /// Newton steps are scaled down to at most this (rad or m) in their largest entry, per
  /// sub-system: with an ill-conditioned Phi_z (wl16_like's, condition ~6e3) a full first step
  /// can overshoot out of the basin; near the solution the steps are far smaller and Newton stays
  /// quadratic.
  double max_step = 0.1;
  /// Smallest / largest |R_ii| of Phi_z below this: singular. At a dead point the closure has a
  /// double root, which Newton approaches only to ~sqrt(tolerance) = 1e-6 before the residual
  /// test stops it, and the pivot ratio there is of that order (the slider-crank of
  /// test_closure_positions comes within 7.4e-6 in 18 steps): 1e-5, just above it, is the finest
  /// distinction the residual tolerance supports (z moving 1e5 times faster than y counts as the
  /// dead point).
  double singular_tolerance = 1e-5;
  /// A converged pose is a dead point when a sub-system's pivot ratio, divided by its ratio at
  /// the assembled pose (SubSystem::nominal_pivot_ratio), is below this. Why relative, and why
  /// this value: near a dead point the closure is quadratic along Phi_z's null direction (its
  /// curvature h), so Newton leaves the smallest pivot sigma and the residual r in the relation
  /// sigma^2 ~= 2 h r (the slider-crank: 2.4 per metre of residual in the pivot ratio squared,
  /// at r = 2e-11 in double and at 1.5e-6 in float alike); a pose closed to the tolerance is
  /// therefore within reach of a dead point when sigma^2 < 2 h tolerance. h is a property of the
  /// linkage; its assembled pose, a residual distance D from the nearest dead point, has
  /// sigma_0^2 ~= 2 h D (the slider-crank: 0.42^2 / 2.4 = 73 mm, for 60 mm of slider travel),
  /// so the test becomes (sigma / sigma_0)^2 < tolerance / D, free of h and of the rows' and
  /// columns' units (sigma_max, the ratio's denominator, changes little: 0.12 to 0.18 there).
  /// D is taken as 5 mm of closure residual (a few mrad times a link): assembled poses lie
  /// farther inside their stroke, and a true D above 5 mm widens the flagged zone to
  /// tolerance x D / 5 mm (the slider-crank in float: 30 um of its 60 mm stroke), one below
  /// narrows it. Hence sqrt(tolerance / 5e-3):
  /// sqrt(1e-12 / 5e-3) = 1.4e-5 here (in double the singular_tolerance test above fires first:
  /// the dead point is found in the same steps as before), sqrt(2e-6 / 5e-3) = 2e-2 for float's
  /// tolerance of 2e-6 (the generated closure_options_float): the slider-crank's stroke end reads
  /// 4.5e-3 in float, the loop robots' regular poses >= 0.4 at test_closure_positions' poses and
  /// >= 8e-2 after moves of 0.3 rad (docs/loops.md): a factor 4 or more either side.
  double dead_point_tolerance = 1.4e-5;
};

/// The options for scalar S: ClosureOptions{} in double; in float the generated code's
/// closure_options_float (a float Newton stops at ~1e-6 of residual: tolerance 2e-6, singular
/// below a pivot ratio of 1e-3, a dead point below a relative one of 2e-2, as derived above).
template <typename S> ClosureOptions default_closure_options() {
  ClosureOptions options;
  if constexpr (std::is_same_v<S, float>) {
    options.tolerance = 2e-6;
    options.singular_tolerance = 1e-3;
    options.dead_point_tolerance = 2e-2;
  }
  return options;
}

template <typename S> struct ClosureResult {
  ClosureStatus status = ClosureStatus::Converged;
  int iterations = 0;      ///< steps taken: Newton's, and simplified ones (closure_positions)
  S residual = S(0);       ///< max |Phi| over the kept rows at the returned q; NaN if q is not finite off the loops
  /// subsystem_pivot_ratio at the returned q (1 without loops); when the final iterate was
  /// checked by its residual alone (closure_positions), at the last Newton iterate, one or two
  /// steps before.
  S pivot_ratio = S(1);
  S relative_pivot_ratio = S(1);  ///< subsystem_relative_pivot_ratio, at the same q as pivot_ratio
  /// A failure's sub-system (index into Model::subsystems): the one with the worst relative pivot
  /// ratio when Singular, the largest (or a non-finite) kept residual when NotConverged; -1 when
  /// Converged, or when a coordinate off the loops is not finite. The generated closure_positions reports the same.
  int subsystem = -1;
  /// The sub-system of relative_pivot_ratio (the nearest a dead point), converged or not; -1
  /// without loops. The generated closure_positions reports the same.
  int worst_subsystem = -1;
};

namespace detail {

/// q index of each sub-system coordinate (its joint is 1-DoF: SubSystemWork checks it).
inline int q_index_of_coordinate(const Model& model, const SubSystem& sub, std::size_t j) {
  return model.joint(model.body(sub.bodies[j]).joint).idx_q;
}

/// Per sub-system, the step Phi_z^-1 Phi_kept (to subtract from z, in SubSystem::dependent order)
/// in the last column of data.subsystem[k].rhs, from the kept rows of data.Phi and the factor of
/// Phi_z in the sub-system's rotations and R.
template <typename S> void step_from_factor(const Model& model, Data<S>& data) {
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) solve_kept_rows<S>(model, data, k, data.Phi);
}

/// The ingredients of one Newton step at q: data.Phi (all closure rows), and per sub-system the
/// R factor of Phi_z in data.subsystem[k].R and the full step Phi_z^-1 Phi_kept (to subtract
/// from z, in SubSystem::dependent order) in the last column of data.subsystem[k].rhs.
template <typename S> void closure_newton_step(const Model& model, Data<S>& data, const ConstVecRef<S>& q) {
  cycle_placements<S>(model, data, q.data());
  for (const LoopClosure& c : model.closures) {
    if (c.type == ClosureType::Coupling) {
      coupling_jacobian_row<S>(model, c, data.Phi_q.middleRows(c.row_offset, 1));
      data.Phi[c.row_offset] = coupling_residual<S>(model, c, q.data());
      continue;
    }
    const BodyIndex top = cycle_kinematics<S>(model, data, c, nullptr);
    closure_jacobian_rows<S>(model, data, c, top, data.Phi_q.middleRows(c.row_offset, c.rows()));
    closure_residual_rows<S>(data, c, top, data.Phi.data() + c.row_offset);
  }
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    load_dependent_block<S>(model, data, k);
    SubSystemWork<S>& w = data.subsystem[k];
    givens_qr_factor<S>(w.R, model.subsystems[k].rank(), w.rotation_c, w.rotation_s);
  }
  step_from_factor<S>(model, data);
}

/// The dependent velocities of v (nv) from its independent ones, v_z = -Phi_z^-1 Phi_y v_y per
/// sub-system, with the factor of Phi_z and the Phi_q that the last closure_newton_step left (at
/// its q): what full_velocities gives at that q, without a second Jacobian and factorisation.
/// Uses the last column of each sub-system's rhs (the step's).
template <typename S, typename V> void dependent_velocities_from_factor(const Model& model, Data<S>& data, V&& v) {
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    SubSystemWork<S>& w = data.subsystem[k];
    const int r = sub.rank(), p = static_cast<int>(sub.independent.size());
    for (int i = 0; i < r; ++i) {
      S x = S(0);
      for (int c = 0; c < p; ++c)
        x += data.Phi_q(sub.rows[static_cast<std::size_t>(i)], sub.independent[static_cast<std::size_t>(c)]) *
             v[sub.independent[static_cast<std::size_t>(c)]];
      w.rhs(i, p) = x;
    }
    auto column = w.rhs.middleCols(p, 1);
    givens_qr_apply<S>(w.rotation_c, w.rotation_s, r, column, 1);
    upper_triangular_solve<S>(w.R, r, column, 1);
    for (int d = 0; d < r; ++d) v[sub.dependent[static_cast<std::size_t>(d)]] = -w.rhs(d, p);
  }
}

/// max |Phi| over the kept rows of every sub-system; false if one of them is not finite.
template <typename S> bool kept_residual(const Model& model, const Data<S>& data, S& worst) {
  using std::abs;
  using std::isfinite;
  worst = S(0);
  bool finite = true;
  for (const SubSystem& sub : model.subsystems)
    for (int row : sub.rows) {
      finite = finite && isfinite(data.Phi[row]);
      if (abs(data.Phi[row]) > worst) worst = abs(data.Phi[row]);
    }
  return finite;
}

/// The sub-system of the largest kept residual, a non-finite one first (ClosureResult::subsystem).
template <typename S> int worst_residual_subsystem(const Model& model, const Data<S>& data) {
  using std::abs;
  using std::isfinite;
  int worst = 0;
  S largest = S(0);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k)
    for (int row : model.subsystems[k].rows) {
      if (!isfinite(data.Phi[row])) return static_cast<int>(k);
      if (abs(data.Phi[row]) > largest) largest = abs(data.Phi[row]), worst = static_cast<int>(k);
    }
  return worst;
}

/// The sub-system of the worst relative pivot ratio, NaN first (ClosureResult::subsystem).
template <typename S> int worst_pivot_subsystem(const Model& model, const Data<S>& data) {
  int worst = 0;
  S lowest = S(1);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const S relative = pivot_ratio_of<S>(data, k) / S(model.subsystems[k].nominal_pivot_ratio);
    if (!(relative >= lowest)) lowest = relative, worst = static_cast<int>(k);
  }
  return worst;
}

/// Whether the iterate after a Newton step is checked by its residual alone (closure_residual:
/// the kinematics of the loop bodies, no Jacobian, no factorisation) before a full step is paid
/// for. Newton converging quadratically has residual_{k+1} ~ K residual_k^2, and K estimated from
/// the last two residuals (K ~ residual_k / residual_{k-1}^2) predicts residual_{k+1} ~
/// residual_k^3 / residual_{k-1}^2: tried when that is below the tolerance. Only where the last
/// factor was far from singular (pivot ratios 100 times their tolerances), since the result then
/// reports that factor's ratios, one step away from the returned q: near a dead point the
/// ratios move with the residual (sigma^2 ~ 2 h r, ClosureOptions::dead_point_tolerance), and
/// there every check keeps its full factorisation.
///
/// A failed try is not wasted: its residual and the factor of the Newton step just taken give a
/// simplified Newton step (step_from_factor: the same rotations and R, no Jacobian, no
/// factorisation), then the residual is checked again; a second failure in a row pays for a full
/// step. The factor is one step old, so the simplified step contracts the residual by about
/// kappa(Phi_z) |Phi_zz| |last step| (linear, not quadratic), and the check is tried only where the
/// last step was small enough to predict a closed iterate: from warm starts 1e-3 off, Newton's
/// third step meets a residual of ~1e-11 (the tolerance 1e-12 is just missed) that the simplified
/// step brings to ~1e-15 (cassie_like, digit_like_2legs: docs/loops.md).
///
/// The first step has no previous residual; there, and at any step, the step's own size predicts
/// too: Newton's next residual is about r |step| (the closure's second derivative over its first,
/// about one per radian for linkages of rotating links: 0.3-2 on the parallel_legs robots), and
/// the simplified step's after it about r |step|^2 (0.3-2.2 times that, measured from starts 1e-4
/// to 1e-2 off). So the check is tried when r |step|^2 is below the tolerance: from a
/// simulator's predicted start (q + h v, residuals 1e-7 to 1e-5 at h = 1 ms) the first step is
/// checked by its residual alone instead of a second Newton step; from a start 1e-3 off it is
/// not (r |step|^2 ~ 1e-7), as before. |step| is the largest entry of any sub-system's step
/// before max_step scales it (rad or m).
template <typename S>
bool residual_check_predicted(const ClosureResult<S>& last, S previous_residual, S largest_step, const ClosureOptions& options) {
  const S r = last.residual;
  const bool quadratic = previous_residual > S(0) && r * r * r < S(options.tolerance) * previous_residual * previous_residual;
  const bool small_step = r * largest_step * largest_step < S(options.tolerance);
  return (quadratic || small_step) && last.pivot_ratio >= S(100 * options.singular_tolerance) &&
         last.relative_pivot_ratio >= S(100 * options.dead_point_tolerance);
}

/// closure_positions; with factor_at_solution (close_loops) every iterate gets the full step, so
/// that the factor of Phi_z left in data is the one at the returned q.
template <typename S>
ClosureResult<S> close_positions(const Model& model, Data<S>& data, Eigen::Ref<VecX<S>> q, const ClosureOptions& options,
                                 bool factor_at_solution) {
  using std::abs;
  ClosureResult<S> result;
  // A non-finite coordinate is no pose, closed or not. The rows read only the loops' own
  // coordinates (closure.hpp), where Newton finds a NaN and names its sub-system; one elsewhere
  // (a floating base's) would not reach them.
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex b(k);
    const Joint& joint = model.joint(model.body(b).joint);
    if (model.structure().subsystem_of_body[b] < 0 && !q.segment(joint.idx_q, joint.nq).allFinite()) {
      result.status = ClosureStatus::NotConverged;
      result.residual = std::numeric_limits<S>::quiet_NaN();
      return result;
    }
  }
  S previous_residual = S(-1);  // the residual before the last step (-1: no step yet)
  bool residual_check = false;
  bool factor_is_last_steps = false;  // data holds the factor of the Newton step just taken
  // Each sub-system's step from the rhs' last column, scaled to max_step in its largest entry;
  // returns the largest entry of any, unscaled.
  const auto take_step = [&] {
    S largest_step = S(0);
    for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
      const SubSystem& sub = model.subsystems[k];
      const SubSystemWork<S>& w = data.subsystem[k];
      const SubSystemLayout& layout = model.structure().subsystems[k];
      const int p = static_cast<int>(sub.independent.size());
      S largest = S(0);
      for (int d = 0; d < sub.rank(); ++d)
        if (abs(w.rhs(d, p)) > largest) largest = abs(w.rhs(d, p));
      const S scale = largest > S(options.max_step) ? S(options.max_step) / largest : S(1);
      for (std::size_t j = 0; j < sub.coordinates.size(); ++j)
        if (layout.coordinate_role[j] < 0) q[detail::q_index_of_coordinate(model, sub, j)] -= scale * w.rhs(-1 - layout.coordinate_role[j], p);
      if (largest > largest_step) largest_step = largest;
    }
    return largest_step;
  };
  for (;; ++result.iterations) {
    if (residual_check) {  // the pivot ratios stay the last factor's (residual_check_predicted)
      cycle_placements<S>(model, data, q.data());
      residual_from_placements<S>(model, data, q.data());
      S residual;
      const bool finite = kept_residual<S>(model, data, residual);
      if (finite && residual < S(options.tolerance)) {
        result.residual = residual;
        return result;
      }
      // Not closed yet: one simplified step with the last factor (residual_check_predicted).
      if (finite && factor_is_last_steps && result.iterations < options.max_iterations) {
        step_from_factor<S>(model, data);
        take_step();
        factor_is_last_steps = false;
        previous_residual = residual;
        continue;
      }
    }
    detail::closure_newton_step<S>(model, data, q);
    const bool finite = detail::kept_residual<S>(model, data, result.residual);
    result.pivot_ratio = subsystem_pivot_ratio<S>(model, data);
    result.relative_pivot_ratio = subsystem_relative_pivot_ratio<S>(model, data);
    result.worst_subsystem = model.subsystems.empty() ? -1 : detail::worst_pivot_subsystem<S>(model, data);
    const auto fail = [&](ClosureStatus status) {
      result.status = status;
      result.subsystem = status == ClosureStatus::Singular ? detail::worst_pivot_subsystem<S>(model, data)
                                                           : detail::worst_residual_subsystem<S>(model, data);
      return result;
    };
    if (!finite) return fail(ClosureStatus::NotConverged);
    if (!(result.pivot_ratio >= S(options.singular_tolerance))) return fail(ClosureStatus::Singular);
    if (result.residual < S(options.tolerance))
      return result.relative_pivot_ratio >= S(options.dead_point_tolerance) ? (result.status = ClosureStatus::Converged, result)
                                                                             : fail(ClosureStatus::Singular);
    if (result.iterations == options.max_iterations) return fail(ClosureStatus::NotConverged);
    const S largest_step = take_step();
    residual_check = !factor_at_solution && residual_check_predicted<S>(result, previous_residual, largest_step, options);
    factor_is_last_steps = true;
    previous_residual = result.residual;
  }
}

}  // namespace detail

/// Closes the loops: solves Phi(y, z) = 0 for the dependent coordinates z of every sub-system by
/// Newton, y and the warm start of z taken from q (nq), z written back into q. Uses data.Phi,
/// data.Phi_q and the sub-systems' factor memory (the maps must be recomputed afterwards, as
/// aba() and forward_dynamics_loops do themselves); it places only the cycles' bodies
/// (detail::cycle_placements), so data's world poses are not the returned q's. When Newton
/// converges quadratically and far from a dead point, the final iterate is checked by its
/// residual alone, and when that is not yet below the tolerance, one simplified step with the
/// last factor precedes the next check (detail::residual_check_predicted): the result's pivot
/// ratios are then those of the last factorisation, one or two steps before the returned q, and
/// the returned q is closed to the tolerance as Newton's (close_loops') is, not the same bits.
template <typename S>
ClosureResult<S> closure_positions(const Model& model, Data<S>& data, Eigen::Ref<VecX<S>> q, const ClosureOptions& options = {}) {
  return detail::close_positions<S>(model, data, q, options, false);
}

/// Closes the loops and makes v consistent with them in one pass: closure_positions, then, when
/// it converged, the dependent entries of v (nv) from its independent ones at the closed q
/// (v = T vy, as full_velocities), from the factor of the Newton step that found q closed. The
/// simulator's projection after each step (sim::Simulator). v is left alone unless Converged.
template <typename S>
ClosureResult<S> close_loops(const Model& model, Data<S>& data, Eigen::Ref<VecX<S>> q, Eigen::Ref<VecX<S>> v,
                             const ClosureOptions& options = {}) {
  const ClosureResult<S> result = detail::close_positions<S>(model, data, q, options, true);
  if (result.status == ClosureStatus::Converged) detail::dependent_velocities_from_factor<S>(model, data, v);
  return result;
}

}  // namespace mbgen
