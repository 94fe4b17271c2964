#pragma once
// The loops as soft constraints: how the simulator continues through a linkage's dead point
// (docs/simulation.md, "Through a dead point"; SimulatorOptions::continuation).
//
// The simulator's state is (q, v) of the spanning tree; normally the dynamics are those of the
// independent coordinates (v = T vy) and every step ends by closing the loops exactly. At a dead
// point a sub-system's Phi_z is singular: T does not exist there and Newton cannot close the
// loop, so that exact path ends with closure_lost. The mechanism itself is regular there (the
// slider-crank's stroke end: the crank turns on and the slider comes back), and in full
// coordinates its constraints usually keep their rank (the independent coordinate's column
// supplies what Phi_z lost). So during a continuation span the simulator integrates the full
// coordinates with the kept closure rows (the backend's closure_constraints) as constraints in
// the form MuJoCo gives its equality constraints: multipliers from
//   (A + R) lambda = a_ref - J a0,   A = J M^-1 J^T,   a0 = M^-1 (tau - C),
//   a_ref = gamma - b J v - k Phi,   b = 2 / t_c, k = 1 / t_c^2 (critically damped, time constant t_c),
//   R = (1 - d) / d diag(A)          (d the impedance: d -> 1 is the hard constraint),
// and qdd = a0 + M^-1 J^T lambda. R keeps A + R positive definite where J does lose rank (a true
// singularity of the mechanism); the reference acceleration pulls the rows back to zero, so the
// violation stays of the order of (1 - d) times the load's acceleration times t_c^2 and decays
// when the load goes. A span begins where the exact step fails to close the loops, or closes them
// with a sub-system's pivot ratio (relative to its assembled pose's, as the dead-point test of
// closure_positions.hpp measures it) below enter_pivot_ratio; nothing is projected during it; it
// ends when Newton closes the loops from the soft state with every ratio back above
// exit_pivot_ratio, and the simulator takes that closed state.
//
// Cost: one mass matrix, one inverse dynamics at zero acceleration, one Cholesky of M and one of
// A per evaluation, O(nv^3): a span is meant to be short, and the exact path resumes after it.
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "mbgen/sim/contact.hpp"

namespace mbgen::sim {

/// SimulatorOptions::continuation.
struct ContinuationOptions {
  /// Off (the default): a step whose loops cannot be closed ends with closure_lost, the state
  /// restored (the exact behaviour). On: the step is taken again with the loops soft, and the run
  /// goes on through a continuation span.
  bool enabled = false;
  /// s: t_c of the soft rows (at least 2 steps are used: the explicit integrators' stability).
  /// Both defaults are far stiffer than MuJoCo's (0.02 s, d 0.9 to 0.95): a span is to carry the
  /// loop through its dead point and give it back closed, not to model a compliant linkage, and
  /// the motion's error through a span goes as 1 - d (docs/simulation.md: the slider-crank
  /// through four dead points follows the exact motion to 1.4e-6 rad with these, 1.4e-3 with
  /// d = 0.999).
  double time_constant = 0.01;
  /// d in (0, 1): how hard the rows are (R = (1 - d) / d diag(A)); R is what keeps A + R regular
  /// where J itself loses rank.
  double impedance = 0.999999;
  /// A span also begins when an exact step closes the loops with a sub-system's pivot ratio,
  /// relative to its assembled pose's, below this (the dead-point test's tolerance is 2e-2): the
  /// exact step in the independent coordinates loses its accuracy before Newton fails (the
  /// slider-crank at 1 ms: 1.7 J of its 3 J lost in the last exact step before its dead point).
  double enter_pivot_ratio = 0.2;
  /// Leave the span when the loops close again with every sub-system's relative pivot ratio at
  /// least this (above enter_pivot_ratio: the margin keeps a span from ending and beginning again
  /// every other step).
  double exit_pivot_ratio = 0.3;
  int max_spans = 64;  ///< spans kept in the report (further ones are counted in the statistics)
};

/// One continuation span, as the simulator reports it.
struct ContinuationSpan {
  double begin = 0;      ///< s: the time the first soft step started from
  double end = -1;       ///< s: the time the loops closed again (-1 while the span is open)
  int subsystem = -1;    ///< the sub-system whose closure failed (Backend::subsystem_name), -1: the step diverged
  bool diverged = false; ///< the span began with a non-finite step rather than a failed closure
  long steps = 0;        ///< accepted soft steps
  double max_violation = 0;  ///< m or rad: the largest |Phi| of the kept rows over the span's accepted states
};

/// The ground's joint forces from the backend's spheres: contact_points (centres into points, 3
/// per sphere, and 6 x nv Jacobians into jacobians), the law at each sphere (sim/contact.hpp) and
/// J_w^T f at its witness, J_w = J_lin - [d]x J_ang with d = -r n: added to tau (nv); one report
/// per sphere into reports if given. The joint-space form the soft span needs (the generated
/// contact_accelerations applies the same law as body forces inside its recursion).
template <typename Backend, typename S>
void add_ground_joint_forces(Backend& backend, const GroundPlane& ground, const ContactParameters& parameters, const S* q,
                             const S* v, S* points, S* jacobians, S* tau, ContactReport<S>* reports) {
  using Block = Eigen::Map<const Eigen::Matrix<S, 6, Eigen::Dynamic, Eigen::RowMajor>>;
  const int nv = backend.nv();
  const Eigen::Map<const VecX<S>> vm(v, nv);
  Eigen::Map<VecX<S>> taum(tau, nv);
  backend.contact_points(q, points, jacobians);
  const Vec3<S> n = ground.normal.template cast<S>();
  for (int k = 0; k < backend.num_contacts(); ++k) {
    const Block J(jacobians + 6 * nv * k, 6, nv);
    const double r = backend.contact_radius(k);
    const Vec3<S> c(points[3 * k], points[3 * k + 1], points[3 * k + 2]);
    const Vec3<S> v_c = J.template topRows<3>() * vm, omega = J.template bottomRows<3>() * vm;
    const ContactReport<S> f = contact_law<S>(c, v_c, omega, r, ground, parameters);
    if (reports) reports[k] = f;
    if (!f.active) continue;
    const Vec3<S> moment = (-S(r) * n).cross(f.force);  // J_ang^T (d x f) is -J_ang^T [d]x^T f
    taum.noalias() += J.template topRows<3>().transpose() * f.force;
    taum.noalias() += J.template bottomRows<3>().transpose() * moment;
  }
}

/// Work memory and the solve of the soft-loop dynamics, sized at construction (no allocation in
/// a call). S the backend's scalar.
template <typename S> class SoftLoops {
 public:
  SoftLoops() : SoftLoops(0, 0) {}
  SoftLoops(int nv, int rows)
      : nv_(nv), rows_(rows), M_(VecX<S>::Zero(nv * nv)), J_(VecX<S>::Zero(rows * nv)), Mm_(MatX<S>::Zero(nv, nv)),
        Jm_(MatX<S>::Zero(rows, nv)), Y_(MatX<S>::Zero(nv, rows)), A_(MatX<S>::Zero(rows, rows)), C_(VecX<S>::Zero(nv)),
        zero_(VecX<S>::Zero(nv)), a0_(VecX<S>::Zero(nv)), Phi_(VecX<S>::Zero(rows)), gamma_(VecX<S>::Zero(rows)),
        rhs_(VecX<S>::Zero(rows)), Jv_(VecX<S>::Zero(rows)), lambda_(VecX<S>::Zero(rows)), llt_M_(nv), llt_A_(rows) {
    // Eigen's sized LLT leaves its status unset until a first factorisation, and the simulator
    // moves this object before any (docs/reliability.md): factorise once here.
    llt_M_.compute(MatX<S>::Identity(nv, nv));
    llt_A_.compute(MatX<S>::Identity(rows, rows));
  }

  /// qdd (nv) at (q, v) under the joint forces tau (nv, everything but the loops' own: control,
  /// stops, contacts). Returns false when M or A + R is not positive definite (qdd is NaN then).
  template <typename Backend>
  bool accelerations(Backend& backend, const ContinuationOptions& o, double step, const S* q, const S* v, const S* tau, S* qdd) {
    using RowMajor = Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
    const Eigen::Map<const VecX<S>> vm(v, nv_), taum(tau, nv_);
    Eigen::Map<VecX<S>> out(qdd, nv_);
    backend.mass_matrix(q, M_.data());
    Mm_ = RowMajor(M_.data(), nv_, nv_);
    backend.inverse_dynamics(q, v, zero_.data(), C_.data());  // Coriolis, centrifugal, gravity
    llt_M_.compute(Mm_);
    if (llt_M_.info() != Eigen::Success) return out.setConstant(S(NAN)), false;
    a0_ = taum - C_;
    llt_M_.solveInPlace(a0_);
    if (rows_ > 0) {
      backend.closure_constraints(q, v, Phi_.data(), J_.data(), gamma_.data());
      Jm_ = RowMajor(J_.data(), rows_, nv_);
      Y_ = Jm_.transpose();
      llt_M_.solveInPlace(Y_);  // M^-1 J^T
      A_.noalias() = Jm_ * Y_;
      const S soften = S((1 - o.impedance) / o.impedance);
      // A row J cannot move at all (a zero diagonal) gets a ridge of the largest one's scale.
      const S floor = S(1e-12) * std::max(A_.diagonal().maxCoeff(), S(1e-300));
      for (int i = 0; i < rows_; ++i) A_(i, i) += soften * A_(i, i) + floor;
      const double tc = std::max(o.time_constant, 2 * step);
      Jv_.noalias() = Jm_ * vm;
      rhs_ = gamma_ - S(2 / tc) * Jv_ - S(1 / (tc * tc)) * Phi_;
      rhs_.noalias() -= Jm_ * a0_;
      llt_A_.compute(A_);
      if (llt_A_.info() != Eigen::Success) return out.setConstant(S(NAN)), false;
      lambda_ = rhs_;
      llt_A_.solveInPlace(lambda_);
      out = a0_;
      out.noalias() += Y_ * lambda_;
    } else {
      out = a0_;
    }
    return true;
  }

  /// The kept rows' largest |Phi| at q (v only feeds the bias, unused here).
  template <typename Backend> double violation(Backend& backend, const S* q, const S* v) {
    if (rows_ == 0) return 0;
    backend.closure_constraints(q, v, Phi_.data(), J_.data(), gamma_.data());
    return static_cast<double>(Phi_.cwiseAbs().maxCoeff());
  }

 private:
  int nv_ = 0, rows_ = 0;
  VecX<S> M_, J_;  ///< row-major buffers the backend writes
  MatX<S> Mm_, Jm_, Y_, A_;
  VecX<S> C_, zero_, a0_, Phi_, gamma_, rhs_, Jv_, lambda_;
  Eigen::LLT<MatX<S>> llt_M_, llt_A_;
};

}  // namespace mbgen::sim
