#pragma once
// Simulator<Backend>: the robot on the ground (docs/simulation.md). Header-only, templated on the
// backend (sim/backend.hpp; a generated NAME::Backend or a runtime one), no allocation in a step.
//
// State: q (nq), every tree joint's position, and v (nv), every tree joint's velocity. With
// `project` on (the default) every accepted step ends by re-closing the loops and projecting the
// velocities (v = T vy from the independent ones) in one pass (the backend's close_loops,
// warm-started: the last Newton step's factor gives the velocities), so the state is exactly (closed q, vy), as the generated API wants; with it off the
// dependent coordinates are integrated as they come, and their drift (the distance Newton moves
// them when the loops are closed on demand, closure_drift()) can be measured. A floating base's
// quaternion is renormalised after every step and at every stage.
//
// The backend's joint ranges are end stops (sim/joint_stops.hpp; SimulatorOptions::joint_stops):
// compliant, in the ground's law, their torques at every stage, their springs in the energy.
//
// Each step returns a status and never leaves a NaN in the state: a failing step restores the
// state it started from, and the simulation is meant to stop there (run_until() does). With
// SimulatorOptions::continuation on, a step whose loops cannot be closed (a linkage's dead point)
// is taken again with the loops as soft constraints in full coordinates (sim/soft_loops.hpp), and
// the run goes on through a continuation span, its steps' status `continued`, until the loops
// close again well away from the dead point; each span is reported (continuation_spans()).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <limits>
#include <vector>

#include <Eigen/LU>
#include <unsupported/Eigen/AutoDiff>

#include "mbgen/sim/backend.hpp"
#include "mbgen/sim/contact.hpp"
#include "mbgen/sim/integrators.hpp"
#include "mbgen/sim/joint_stops.hpp"
#include "mbgen/sim/soft_loops.hpp"
#include "mbgen/sim/state_space.hpp"

namespace mbgen::sim {

enum class StepStatus {
  ok,              ///< the step was taken
  step_rejected,   ///< adaptive integrator: the error estimate was too large; the step is retried smaller
                   ///< (run_until stops with it when the step would fall below min_step)
  closure_lost,    ///< closure_positions did not converge, or a linkage reached a dead point
  diverged,        ///< a non-finite state or joint force, or the energy grew beyond its bound
  penetration,     ///< a contact sphere sank deeper than max_penetration
  continued,       ///< the step was taken with the loops soft, in a continuation span (SimulatorOptions::continuation)
};

/// Whether a step's status means it was taken (ok, or continued through a dead point).
inline bool advanced(StepStatus s) { return s == StepStatus::ok || s == StepStatus::continued; }

inline const char* to_string(StepStatus s) {
  switch (s) {
    case StepStatus::ok: return "ok";
    case StepStatus::step_rejected: return "step_rejected";
    case StepStatus::closure_lost: return "closure_lost";
    case StepStatus::diverged: return "diverged";
    case StepStatus::penetration: return "penetration";
    case StepStatus::continued: return "continued";
  }
  return "unknown";
}

struct SimulatorOptions {
  Integrator integrator = Integrator::rk4;
  double step = 1e-4;        ///< s: the fixed step, or the adaptive integrator's first step
  double rtol = 1e-6;        ///< dormand_prince45: relative tolerance on each state entry
  double atol = 1e-8;        ///< dormand_prince45: absolute tolerance (m, rad, m/s, rad/s)
  double min_step = 1e-10;   ///< s: dormand_prince45 stops with step_rejected below it
  double max_step = 1e-2;    ///< s: dormand_prince45's largest step
  bool project = true;       ///< re-close the loops and project the velocities after each step
  /// m or rad: the largest closure residual the projection leaves (or the backend scalar's own
  /// Newton tolerance, the larger: 2e-6 for float). Why not the closure's 1e-12: the angular
  /// closure rows drift by O(h^2) per step (their velocity rows are the position rows'
  /// derivative only at closed poses; docs/simulation.md), 4e-12 rad per 1e-4 s step on Lola
  /// standing, so a 1e-12 tolerance costs every step a second Newton evaluation and buys no
  /// accuracy the integrator keeps: its own position error per step is larger.
  double closure_tolerance = 1e-11;
  bool contact = true;       ///< the ground acts on the backend's contact spheres
  GroundPlane ground;
  ContactParameters contact_parameters;
  double max_penetration = 0.05;  ///< m: deeper is a failure (the contact model is meaningless there)
  /// J: the mechanical energy (kinetic, gravity, contact springs) minus the controller's work
  /// may not grow by more than this; <= 0 picks 0.1 m |g| x 1 m (a tenth of lifting the robot
  /// by a metre). Checked every energy_check_interval accepted steps (0: never).
  double energy_limit = 0;
  int energy_check_interval = 10;
  double control_period = 1e-3;  ///< s: the controller runs at this rate (zero-order hold); 0: every step
  /// The end stops at the backend's joint ranges (on by default; `scene: joint_limits`). Taken at
  /// set_state, where each default stiffness is fixed from the start pose's inertia.
  JointStopParameters joint_stops;
  /// Through a dead point: off by default (the step ends with closure_lost); on, the loops turn
  /// soft until they can be closed again (sim/soft_loops.hpp). Needs a backend with
  /// closure_constraints.
  ContinuationOptions continuation;
};

/// What a run did, for the study and the reports.
struct SimulationStatistics {
  long accepted_steps = 0, rejected_steps = 0, evaluations = 0, controller_calls = 0;
  double max_penetration = 0;    ///< m, over the accepted states
  double max_stop_penetration = 0;  ///< rad or m past a joint's range, over the accepted states
  double last_step = 0;          ///< s
  long soft_steps = 0;           ///< accepted steps with the loops soft (continuation spans)
  long continuation_spans = 0;   ///< spans begun (continuation_spans() keeps the first max_spans)
  double max_loop_violation = 0; ///< m or rad: the largest |Phi| of the kept closure rows over the spans
};

namespace detail {
template <typename B, typename = void> struct has_closure_constraints : std::false_type {};
template <typename B>
struct has_closure_constraints<B, std::void_t<decltype(std::declval<B&>().closure_constraints(nullptr, nullptr, nullptr, nullptr, nullptr))>>
    : std::true_type {};
}  // namespace detail

template <typename Backend> class Simulator {
 public:
  using S = typename Backend::Scalar;
  using Controller = std::function<void(double t, const S* q, const S* v, S* tau)>;

  Simulator(Backend backend, const SimulatorOptions& options = {})
      : backend_(std::move(backend)), options_(options), nq_(backend_.nq()), nv_(backend_.nv()), ny_(backend_.ny()),
        nc_(backend_.num_contacts()) {
    const auto vec = [](int n) { return VecX<S>::Zero(n); };
    q_ = vec(nq_), v_ = vec(nv_), q_start_ = vec(nq_), v_start_ = vec(nv_), q_stage_ = vec(nq_), v_stage_ = vec(nv_);
    q_eval_ = vec(nq_), tau_control_ = vec(nv_), tau_total_ = vec(nv_), tau_passive_ = vec(nv_);
    for (int s = 0; s < kMaxStages; ++s) dq_[s] = vec(nq_), dv_[s] = vec(nv_);
    q_error_ = vec(nq_), v_error_ = vec(nv_);
    points_ = vec(3 * nc_), jacobians_ = vec(6 * nv_ * nc_), contact_out_ = vec(kContactOutputs * nc_);
    reports_.resize(static_cast<std::size_t>(nc_));
    implicit_.resize(nq_, nv_, ny_);
    stops_.reserve(backend_.num_limited_joints());
    if (backend_.floating_base()) q_[6] = S(1);
    step_ = options_.step;
    if constexpr (detail::has_closure_constraints<Backend>::value) soft_ = SoftLoops<S>(nv_, backend_.num_closure_rows());
    const double* g = backend_.gravity();
    gravity_norm_ = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  }

  // --- state --------------------------------------------------------------------------------
  /// Sets the state (q: nq, v: nv) and the time; with project on, closes the loops and projects v
  /// first, and returns that closure's status (0 converged).
  int set_state(const S* q, const S* v, double t = 0) {
    for (int i = 0; i < nq_; ++i) q_[i] = q[i];
    for (int i = 0; i < nv_; ++i) v_[i] = v[i];
    normalize_quaternion<S>(backend_.floating_base(), q_.data());
    t_ = t;
    control_ticks_ = 0;
    work_ = 0;
    int closure = 0;
    in_span_ = false;
    spans_.clear();
    if (options_.continuation.enabled) {
      if (!detail::has_closure_constraints<Backend>::value)
        throw std::invalid_argument("Simulator: continuation through a dead point needs the backend's closure_constraints "
                                    "(regenerate the robot: the `simulation` output brings it)");
      spans_.reserve(static_cast<std::size_t>(std::max(0, options_.continuation.max_spans)));
    }
    if (options_.project) closure = project();
    configure_stops();
    adopt_contact_exponent();
    energy_start_ = energy();
    stats_ = {};
    control_due_ = true;
    return closure;
  }
  const VecX<S>& q() const { return q_; }
  const VecX<S>& v() const { return v_; }
  double time() const { return t_; }
  Backend& backend() { return backend_; }
  /// Changes apply from the next step; contact_parameters.exponent is taken (runtime backends) or
  /// checked against the generated law (generated ones) at set_state.
  SimulatorOptions& options() { return options_; }
  const SimulationStatistics& statistics() const { return stats_; }
  /// The joint forces the controller wrote last (held until its next call), nv.
  const VecX<S>& control_forces() const { return tau_control_; }
  void set_controller(Controller controller) { controller_ = std::move(controller); }
  /// Passive joint forces (springs, dampers): a law of the state, evaluated at every stage of
  /// every step, unlike the controller's zero-order hold (a stiff spring held over a step is
  /// explicit Euler on it, and gains energy). It adds to tau (nv). Its work enters the energy
  /// balance like the controller's.
  using PassiveForces = std::function<void(const S* q, const S* v, S* tau)>;
  void set_passive_forces(PassiveForces passive) { passive_ = std::move(passive); }
  const PassiveForces& passive_forces() const { return passive_; }
  /// The end stops, evaluated at the current state (each one's torque, penetration, and its
  /// activity since set_state).
  const std::vector<JointStopReport<S>>& joint_stops() {
    evaluate(q_, v_, dq_[0], dv_[0], true);
    return stops_.reports();
  }
  /// The last closure_positions status (0 converged, 1 not converged, 2 singular): why a step
  /// ended in closure_lost.
  int closure_status() const { return closure_status_; }
  /// The sub-system that closure failed in (Backend::subsystem_name(k) names it), -1 if none.
  int closure_subsystem() const { return closure_subsystem_; }
  /// Whether the loops are soft now (a continuation span is open).
  bool in_continuation() const { return in_span_; }
  /// The continuation spans since set_state (the first continuation.max_spans of them), the last
  /// one open while in_continuation().
  const std::vector<ContinuationSpan>& continuation_spans() const { return spans_; }

  // --- stepping -----------------------------------------------------------------------------
  /// One step of the configured integrator (no longer than `max_dt`, and ending at the next
  /// controller call at the latest). ok: time and state advanced; any other status: the state
  /// is the one the step started from.
  StepStatus step(double max_dt = std::numeric_limits<double>::infinity()) {
    if (control_due_ && !run_controller()) return StepStatus::diverged;
    double h = options_.integrator == Integrator::dormand_prince45 ? std::min(step_, options_.max_step) : options_.step;
    h = std::min(h, max_dt);
    if (controller_ && options_.control_period > 0)
      h = std::min(h, next_control_time() - t_);
    StepStatus status = advance(h);
    // A dead point (the loops cannot be closed, or the exact dynamics blew up with loops present):
    // the same step again with the loops soft, when asked to.
    const bool loops_failed = status == StepStatus::closure_lost || (status == StepStatus::diverged && step_diverged_ && ny_ < nv_);
    if (loops_failed && options_.continuation.enabled && !in_span_) {
      begin_span(status == StepStatus::diverged);
      status = advance(h);
      if (status != StepStatus::ok) {  // soft failed too: the run ends as it would have
        in_span_ = false;
        if (!spans_.empty() && spans_.back().end < 0) spans_.pop_back();
        --stats_.continuation_spans;
        return status;
      }
    }
    if (status != StepStatus::ok) return status;
    add_work(h);
    // The step's start state (recorded by its first evaluation) is an accepted state now.
    stats_.max_penetration = std::max(stats_.max_penetration, static_cast<double>(max_penetration_));
    stops_.accept(h);
    stats_.max_stop_penetration = static_cast<double>(stops_.max_penetration());
    t_ += h;
    stats_.last_step = h;
    ++stats_.accepted_steps;
    const bool soft = in_span_;
    if (soft) accept_soft_step();
    if (controller_ && options_.control_period > 0 && t_ >= next_control_time() - 1e-12 * options_.control_period) {
      ++control_ticks_;
      control_due_ = true;
    } else if (controller_ && options_.control_period <= 0) {
      control_due_ = true;
    }
    if (options_.energy_check_interval > 0 && stats_.accepted_steps % options_.energy_check_interval == 0) {
      if (!(energy() - energy_start_ - work_ <= energy_limit())) return restore(StepStatus::diverged);
    }
    return soft ? StepStatus::continued : StepStatus::ok;
  }

  /// Steps until time t_end (rejected steps are retried). Returns ok at t_end (continued if any
  /// step on the way was a soft one), or the status that stopped it, with the state the failing
  /// step started from.
  StepStatus run_until(double t_end) {
    bool continued = false;
    while (t_ < t_end - 1e-12 * std::max(1.0, std::abs(t_end))) {
      const StepStatus s = step(t_end - t_);
      if (s == StepStatus::ok) continue;
      if (s == StepStatus::continued) {
        continued = true;
        continue;
      }
      if (s == StepStatus::step_rejected && step_ >= options_.min_step) continue;
      return s;
    }
    return continued ? StepStatus::continued : StepStatus::ok;
  }

  // --- what the state means -----------------------------------------------------------------
  /// Mechanical energy: kinetic (1/2 v^T M v), gravity (-m g . com), the contact springs and the
  /// end stops' springs.
  S energy() {
    backend_.mass_matrix(q_.data(), implicit_.M.data());
    implicit_.v_next.noalias() = implicit_.M_row_major() * v_;
    S e = S(0.5) * v_.dot(implicit_.v_next);
    S com[3];
    backend_.center_of_mass(q_.data(), com);
    const double* g = backend_.gravity();
    e -= S(backend_.total_mass()) * (S(g[0]) * com[0] + S(g[1]) * com[1] + S(g[2]) * com[2]);
    if (options_.contact && nc_ > 0) {
      backend_.contact_points(q_.data(), points_.data(), jacobians_.data());
      for (int k = 0; k < nc_; ++k) {
        const Vec3<S> c(points_[3 * k], points_[3 * k + 1], points_[3 * k + 2]);
        const S delta = S(options_.ground.offset + backend_.contact_radius(k)) - options_.ground.normal.template cast<S>().dot(c);
        e += contact_spring_energy<S>(delta, options_.contact_parameters);
      }
    }
    return e + stops_.energy(q_.data());
  }
  /// Energy minus its start minus the controller's work: zero for an exact, conservative run.
  S energy_balance() { return energy() - energy_start_ - work_; }
  /// The contacts at the current state, one report per sphere of the backend.
  const std::vector<ContactReport<S>>& contacts() {
    evaluate(q_, v_, dq_[0], dv_[0], true);
    return reports_;
  }
  /// How far closure_positions moves the dependent coordinates from the current q (max |dz|,
  /// rad or m): the loops' drift when project is off, ~0 when on. Leaves the state alone.
  S closure_drift() {
    q_stage_ = q_;
    backend_.closure_positions(q_stage_.data());
    return (q_stage_ - q_).cwiseAbs().maxCoeff();
  }

 private:
  static constexpr int kMaxStages = 7;

  struct ImplicitWork {
    void resize(int nq, int nv, int ny) {
      M = VecX<S>::Zero(nv * nv), T = VecX<S>::Zero(nv * ny);
      A = MatX<S>::Zero(nv, nv), B = MatX<S>::Zero(nv, nv);
      My = MatX<S>::Zero(ny, ny), lhs = MatX<S>::Zero(ny, ny), TtA = MatX<S>::Zero(ny, nv), MT = MatX<S>::Zero(nv, ny);
      Ty = MatX<S>::Zero(ny, ny), Tv = VecX<S>::Zero(nv);
      rhs = VecX<S>::Zero(ny), dy = VecX<S>::Zero(ny), ydd0 = VecX<S>::Zero(ny), vy = VecX<S>::Zero(ny);
      Jw = MatX<S>::Zero(3, nv), FJ = MatX<S>::Zero(3, nv), v_next = VecX<S>::Zero(nv);
      lu = Eigen::PartialPivLU<MatX<S>>(ny);
      (void)nq;
    }
    Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> M_row_major() const {
      return {M.data(), v_next.size(), v_next.size()};
    }
    VecX<S> M, T;  ///< row-major buffers the backend writes
    MatX<S> A, B, My, lhs, TtA, MT, Jw, FJ, Ty;
    VecX<S> Tv;
    VecX<S> rhs, dy, ydd0, vy, v_next;
    Eigen::PartialPivLU<MatX<S>> lu;
  };

  double next_control_time() const { return (control_ticks_ + 1) * options_.control_period; }
  double energy_limit() const {
    return options_.energy_limit > 0 ? options_.energy_limit : 0.1 * backend_.total_mass() * gravity_norm_;
  }

  bool run_controller() {
    control_due_ = false;
    if (!controller_) return true;
    controller_(t_, q_.data(), v_.data(), tau_control_.data());
    ++stats_.controller_calls;
    return tau_control_.allFinite();
  }

  bool finite() const { return q_.allFinite() && v_.allFinite(); }

  /// The stops of options_.joint_stops at the backend's ranges, each told the inertia it feels at
  /// the current (start) state (its default stiffness, its damping cap): m = 1 / (t' M_y^-1 t), t
  /// the joint's row of the velocity map and M_y = T' M T (for a tree joint, 1 / (M^-1)_ii: the
  /// articulated inertia about its axis with everything else free).
  void configure_stops() {
    stops_.configure(backend_, options_.joint_stops);
    if (stops_.size() == 0) return;
    ImplicitWork& w = implicit_;
    backend_.mass_matrix(q_.data(), w.M.data());
    backend_.velocity_map(q_.data(), w.T.data());
    const Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> M(w.M.data(), nv_, nv_),
        T(w.T.data(), nv_, ny_);
    w.MT.noalias() = M * T;
    w.My.noalias() = T.transpose() * w.MT;
    w.lu.compute(w.My);
    for (int k = 0; k < stops_.size(); ++k) {
      w.rhs = T.row(stops_.reports()[static_cast<std::size_t>(k)].v_index).transpose();
      w.dy.noalias() = w.lu.solve(w.rhs);
      const double inverse = static_cast<double>(w.rhs.dot(w.dy));
      // A joint no independent coordinate moves (inverse 0) cannot reach its stop: stiffness 0.
      stops_.set_inertia(k, inverse > 0 ? 1 / inverse : 0);
    }
  }
  StepStatus restore(StepStatus s) {
    q_ = q_start_;
    v_ = v_start_;
    return s;
  }

  /// One step of length h from the current state: ok, or a failure with the state restored (the
  /// bookkeeping of an accepted step is step()'s).
  StepStatus advance(double h) {
    step_diverged_ = false;
    h_ = h;
    q_start_ = q_;
    v_start_ = v_;
    // Every integrator starts from f(x_n), which also tells the contacts' state at x_n.
    evaluate(q_, v_, dq_[0], dv_[0], /*record=*/true);
    stage_power_[0] = power_;
    if (max_penetration_ > S(options_.max_penetration)) return StepStatus::penetration;
    StepStatus status = StepStatus::ok;
    Integrator integrator = options_.integrator;
    // The linearly implicit method solves in the independent coordinates, whose velocity map a
    // dead point does not have: symplectic Euler (its explicit part) in a span.
    if (in_span_ && integrator == Integrator::linearly_implicit_euler) integrator = Integrator::symplectic_euler;
    switch (integrator) {
      case Integrator::explicit_euler: explicit_euler(h); break;
      case Integrator::symplectic_euler: symplectic_euler(h); break;
      case Integrator::rk4: explicit_rk(ButcherTableau::rk4(), h); break;
      case Integrator::dormand_prince45: status = dormand_prince(h); break;
      case Integrator::linearly_implicit_euler: linearly_implicit_euler(h); break;
    }
    if (status != StepStatus::ok) return status;
    normalize_quaternion<S>(backend_.floating_base(), q_.data());
    if (!finite()) {
      step_diverged_ = true;
      return restore(StepStatus::diverged);
    }
    if (options_.project && !in_span_) {
      if (project() != 0) return restore(StepStatus::closure_lost);
      // Closed, but near a dead point, where the exact step in the independent coordinates loses
      // its accuracy (the velocity map grows like 1 / pivot ratio, and the projection takes the
      // error out of the kinetic energy): with the continuation on, the span begins here.
      if (options_.continuation.enabled && closure_margin_ < options_.continuation.enter_pivot_ratio) {
        closure_subsystem_ = closure_worst_;
        return restore(StepStatus::closure_lost);
      }
    }
    return StepStatus::ok;
  }

  /// A continuation span begins at the current (restored) state.
  void begin_span(bool diverged) {
    in_span_ = true;
    ++stats_.continuation_spans;
    span_recorded_ = static_cast<int>(spans_.size()) < options_.continuation.max_spans;
    if (!span_recorded_) return;
    ContinuationSpan span;
    span.begin = t_;
    span.subsystem = diverged ? -1 : closure_subsystem_;
    span.diverged = diverged;
    spans_.push_back(span);  // within the capacity reserved at set_state
  }

  /// After an accepted soft step: the violation recorded, and back to the exact closure when
  /// Newton closes the loops from the soft state away from the dead point.
  void accept_soft_step() {
    ++stats_.soft_steps;
    const double violation = soft_.violation(backend_, q_.data(), v_.data());
    stats_.max_loop_violation = std::max(stats_.max_loop_violation, violation);
    ContinuationSpan* span = span_recorded_ ? &spans_.back() : nullptr;
    if (span) {
      ++span->steps;
      span->max_violation = std::max(span->max_violation, violation);
    }
    q_stage_ = q_;
    v_stage_ = v_;
    int subsystem = -1;
    double ratio = 0;
    const int status = backend_.close_loops(q_stage_.data(), v_stage_.data(), options_.closure_tolerance, &subsystem, &ratio);
    if (status != 0 || !(ratio >= options_.continuation.exit_pivot_ratio) || !q_stage_.allFinite() || !v_stage_.allFinite()) return;
    closure_margin_ = ratio;
    q_ = q_stage_;
    v_ = v_stage_;
    in_span_ = false;
    closure_status_ = 0, closure_subsystem_ = -1;
    if (span) span->end = t_;
  }

  /// Closes the loops in q_ and sets v_ = T vy, in one pass (the backend's close_loops); returns
  /// the closure status (0 converged).
  int project() {
    if (ny_ == nv_) return 0;
    return closure_status_ = backend_.close_loops(q_.data(), v_.data(), options_.closure_tolerance, &closure_subsystem_,
                                                  &closure_margin_, &closure_worst_);
  }

  /// The work of the control and passive forces over the accepted step of length h, by the
  /// step's own quadrature: a Runge-Kutta method's weights on its stage powers (the work is one
  /// more state, integrated to the method's order, so that the energy balance measures the
  /// integrator and not a coarser quadrature of it); the trapezoidal rule for the first-order
  /// methods (the power at the end from the forces at the end of the step).
  void add_work(double h) {
    const ButcherTableau* tab = options_.integrator == Integrator::rk4                ? &ButcherTableau::rk4()
                                : options_.integrator == Integrator::dormand_prince45 ? &ButcherTableau::dormand_prince45()
                                                                                      : nullptr;
    if (tab) {
      for (int s = 0; s < tab->stages; ++s) work_ += S(h * tab->b[s]) * stage_power_[s];
      return;
    }
    S power_end = tau_control_.dot(v_);
    if (passive_) {
      tau_passive_.setZero();
      passive_(q_.data(), v_.data(), tau_passive_.data());
      power_end += tau_passive_.dot(v_);
    }
    work_ += S(h / 2) * (stage_power_[0] + power_end);
  }

  /// f(x) = (qdot, vdot) at (q, v) under the held control forces and the ground; `record` keeps
  /// the contact reports and the largest penetration.
  void evaluate(const VecX<S>& q, const VecX<S>& v, VecX<S>& qdot, VecX<S>& vdot, bool record) {
    ++stats_.evaluations;
    q_eval_ = q;
    normalize_quaternion<S>(backend_.floating_base(), q_eval_.data());
    tau_total_ = tau_control_;
    if (passive_) {
      tau_passive_.setZero();
      passive_(q_eval_.data(), v.data(), tau_passive_.data());
      tau_total_ += tau_passive_;
    }
    power_ = (passive_ ? (tau_control_ + tau_passive_).dot(v) : tau_control_.dot(v));
    stops_.add_torques(q_eval_.data(), v.data(), tau_total_.data(), record);
    if (in_span_)
      soft_accelerations(q_eval_, v, vdot, record);
    else if (options_.contact && nc_ > 0)
      contact_accelerations(q_eval_, v, vdot, record);
    else
      backend_.accelerations(q_eval_.data(), v.data(), tau_total_.data(), vdot.data());
    configuration_rate<S>(backend_.floating_base(), nq_, q_eval_.data(), v.data(), qdot.data());
  }

  using RowBlock = Eigen::Map<const Eigen::Matrix<S, 6, Eigen::Dynamic, Eigen::RowMajor>>;

  /// The law's exponent shapes the code (sim/contact.hpp): a runtime backend takes the options',
  /// a generated one is built for its scene's and must match.
  void adopt_contact_exponent() {
    const double e = options_.contact_parameters.exponent;
    if constexpr (detail::has_set_contact_exponent<Backend>::value) {
      backend_.set_contact_exponent(e);
    } else if (options_.contact && nc_ > 0 && backend_.contact_exponent() != e) {
      char message[256];
      std::snprintf(message, sizeof message,
                    "Simulator: contact_parameters.exponent is %g but the generated backend's contact law is built for %g (the "
                    "scene's `contact: exponent`): set the option to it, or regenerate with the exponent wanted",
                    e, backend_.contact_exponent());
      throw std::invalid_argument(message);
    }
  }

  /// f(x) under the ground: the backend adds the contacts' joint forces to tau_total_ and solves
  /// in one call (generated: one unrolled function); `record` keeps the reports.
  void contact_accelerations(const VecX<S>& q, const VecX<S>& v, VecX<S>& vdot, bool record) {
    double g[kGroundInputs], l[kLawInputs];
    contact_inputs(options_.ground, options_.contact_parameters, g, l);
    const S ground[kGroundInputs] = {S(g[0]), S(g[1]), S(g[2]), S(g[3])}, law[kLawInputs] = {S(l[0]), S(l[1]), S(l[2]), S(l[3])};
    backend_.accelerations_with_contact(q.data(), v.data(), tau_total_.data(), ground, law, vdot.data(), contact_out_.data());
    if (!record) return;
    max_penetration_ = S(0);
    for (int k = 0; k < nc_; ++k) {
      const S* o = contact_out_.data() + kContactOutputs * k;
      ContactReport<S>& r = reports_[static_cast<std::size_t>(k)];
      r.penetration = o[0];
      r.point = Vec3<S>(o[1], o[2], o[3]);
      r.active = o[0] > S(0);
      r.force = r.active ? Vec3<S>(o[4], o[5], o[6]) : Vec3<S>::Zero();
      r.slip_velocity = r.active ? Vec3<S>(o[7], o[8], o[9]) : Vec3<S>::Zero();
      r.normal_force = r.force.dot(Vec3<S>(ground[0], ground[1], ground[2]));
      max_penetration_ = std::max(max_penetration_, r.penetration);
    }
  }

  /// f(x) in a continuation span: the loops soft in full coordinates (sim/soft_loops.hpp), the
  /// ground's forces as joint forces J_w^T f at each sphere's witness, by the same law.
  void soft_accelerations(const VecX<S>& q, const VecX<S>& v, VecX<S>& vdot, bool record) {
    if (options_.contact && nc_ > 0) {
      add_ground_joint_forces<Backend, S>(backend_, options_.ground, options_.contact_parameters, q.data(), v.data(), points_.data(),
                                          jacobians_.data(), tau_total_.data(), record ? reports_.data() : nullptr);
      if (record) {
        max_penetration_ = S(0);
        for (const ContactReport<S>& r : reports_) max_penetration_ = std::max(max_penetration_, r.penetration);
      }
    }
    soft_.accelerations(backend_, options_.continuation, h_, q.data(), v.data(), tau_total_.data(), vdot.data());
  }

  void explicit_euler(double h) {
    q_ += S(h) * dq_[0];
    v_ += S(h) * dv_[0];
  }

  /// v first, then q with the new v (symplectic for a separable system).
  void symplectic_euler(double h) {
    v_ += S(h) * dv_[0];
    configuration_rate<S>(backend_.floating_base(), nq_, q_.data(), v_.data(), dq_[1].data());
    q_ += S(h) * dq_[1];
  }

  /// An explicit Runge-Kutta step whose first stage (dq_[0], dv_[0]) is already evaluated.
  void explicit_rk(const ButcherTableau& tab, double h) {
    for (int s = 1; s < tab.stages; ++s) {
      combine(q_, dq_, tab.a[s], s, h, q_stage_);
      combine(v_, dv_, tab.a[s], s, h, v_stage_);
      evaluate(q_stage_, v_stage_, dq_[s], dv_[s], false);
      stage_power_[s] = power_;
    }
    combine(q_, dq_, tab.b, tab.stages, h, q_);
    combine(v_, dv_, tab.b, tab.stages, h, v_);
  }

  /// out = x + sum_j (h w[j]) d[j] over the n stages with w[j] != 0, in one pass (out may be x);
  /// the terms added in stage order, as a sequence of axpys would.
  static void combine(const VecX<S>& x, const VecX<S>* d, const double* w, int n, double h, VecX<S>& out) {
    const S* terms[kMaxStages];
    S weights[kMaxStages];
    int m = 0;
    for (int j = 0; j < n; ++j)
      if (w[j] != 0) terms[m] = d[j].data(), weights[m++] = S(h * w[j]);
    using Map = Eigen::Map<const VecX<S>>;
    const int size = static_cast<int>(x.size());
    const auto t = [&](int k) { return Map(terms[k], size); };
    switch (m) {  // Eigen's vectorised expressions for the common shapes, element by element in stage order
      case 0: out = x; return;
      case 1: out = x + weights[0] * t(0); return;
      case 2: out = x + weights[0] * t(0) + weights[1] * t(1); return;
      case 3: out = x + weights[0] * t(0) + weights[1] * t(1) + weights[2] * t(2); return;
      case 4: out = x + weights[0] * t(0) + weights[1] * t(1) + weights[2] * t(2) + weights[3] * t(3); return;
      default:
        for (int i = 0; i < size; ++i) {
          S acc = x[i];
          for (int k = 0; k < m; ++k) acc += weights[k] * terms[k][i];
          out[i] = acc;
        }
    }
  }

  /// Dormand-Prince 5(4): the fifth-order solution advances, the embedded fourth-order one gives
  /// the error; the step size follows the usual controller (Hairer, Norsett and Wanner, II.4).
  StepStatus dormand_prince(double h) {
    const ButcherTableau& tab = ButcherTableau::dormand_prince45();
    explicit_rk(tab, h);
    q_error_.setZero();
    v_error_.setZero();
    for (int s = 0; s < tab.stages; ++s) {
      const double e = tab.b[s] - tab.b_embedded[s];
      if (e == 0) continue;
      q_error_ += S(h * e) * dq_[s];
      v_error_ += S(h * e) * dv_[s];
    }
    double sum = 0;
    const auto accumulate = [&](const VecX<S>& start, const VecX<S>& end, const VecX<S>& err) {
      for (int i = 0; i < err.size(); ++i) {
        const double scale = options_.atol + options_.rtol * std::max(std::abs(double(start[i])), std::abs(double(end[i])));
        const double r = double(err[i]) / scale;
        sum += r * r;
      }
    };
    accumulate(q_start_, q_, q_error_);
    accumulate(v_start_, v_, v_error_);
    const double err = std::sqrt(sum / (nq_ + nv_));
    if (!std::isfinite(err)) {
      step_ = 0.2 * h;
      ++stats_.rejected_steps;
      restore(StepStatus::step_rejected);
      return step_ < options_.min_step ? StepStatus::diverged : StepStatus::step_rejected;
    }
    const double factor = err == 0 ? 5.0 : std::clamp(0.9 * std::pow(err, -0.2), 0.2, 5.0);
    if (err > 1) {
      step_ = h * std::min(factor, 1.0);
      ++stats_.rejected_steps;
      return restore(StepStatus::step_rejected);
    }
    step_ = std::min(h * factor, options_.max_step);
    return StepStatus::ok;
  }

  /// Linearly implicit Euler on the contact forces: the contacts' stiffness and damping are taken
  /// at the end of the step through their exact Jacobian (automatic differentiation of the law),
  /// everything else as in symplectic Euler. In the independent coordinates y (v = T vy):
  ///   (M_y - h D_y - h^2 K_y) dy = h M_y ydd_0 + h^2 K_y vy,  v+ = v + h vdot_0 + T (dy - h ydd_0),
  /// with M_y = T^T M T, D_y = T^T (sum J_w^T df/dv_w J_w) T, K_y the same with df/dp; then
  /// q+ = q + h qdot(q, v+). Why this method: the stiff part of a legged robot is the contact
  /// (stiffness 1e7, damping), local and cheap to linearise, while the rigid-body dynamics are
  /// not stiff; one ny x ny LU per step makes steps of the order of the contact's own time
  /// constant stable, where the explicit methods need a fraction of it. A Rosenbrock method of
  /// higher order would need the full Jacobian of the dynamics, which neither the generated nor
  /// the generic backends provide.
  void linearly_implicit_euler(double h) {
    ImplicitWork& w = implicit_;
    backend_.mass_matrix(q_eval_.data(), w.M.data());
    backend_.velocity_map(q_eval_.data(), w.T.data());
    const Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> M(w.M.data(), nv_, nv_),
        T(w.T.data(), nv_, ny_);
    w.A.setZero();
    w.B.setZero();
    if (options_.contact && nc_ > 0) {  // the reports of f(x_n) tell which contacts are active
      backend_.contact_points(q_eval_.data(), points_.data(), jacobians_.data());
      contact_jacobians(h);
    }
    stops_.add_jacobians(q_eval_.data(), v_.data(), h, w.A, w.B);
    for (int i = 0; i < ny_; ++i) {
      w.ydd0[i] = dv_[0][backend_.independent_v_index()[i]];
      w.vy[i] = v_[backend_.independent_v_index()[i]];
    }
    w.MT.noalias() = M * T;
    w.My.noalias() = T.transpose() * w.MT;
    w.lhs = w.My;
    // Every product into its own buffer: Eigen would allocate the nested temporaries.
    w.TtA.noalias() = T.transpose() * w.A;  // A holds D + h K (contact_jacobians)
    w.Ty.noalias() = w.TtA * T;
    w.lhs -= S(h) * w.Ty;
    w.rhs.noalias() = w.My * w.ydd0;
    w.rhs *= S(h);
    w.TtA.noalias() = T.transpose() * w.B;  // B holds K
    w.Tv.noalias() = T * w.vy;
    w.dy.noalias() = w.TtA * w.Tv;
    w.rhs += S(h * h) * w.dy;
    w.lu.compute(w.lhs);
    w.dy.noalias() = w.lu.solve(w.rhs);
    w.dy -= S(h) * w.ydd0;
    v_ += S(h) * dv_[0];
    w.Tv.noalias() = T * w.dy;
    v_ += w.Tv;
    configuration_rate<S>(backend_.floating_base(), nq_, q_.data(), v_.data(), dq_[1].data());
    q_ += S(h) * dq_[1];
  }

  /// A = sum J_w^T (df/dv_w + h df/dp) J_w and B = sum J_w^T df/dp J_w over the active contacts,
  /// with J_w = J_lin - [d]x J_ang the witness's Jacobian (d = -r n).
  void contact_jacobians(double h) {
    using AD = Eigen::AutoDiffScalar<Eigen::Matrix<S, 6, 1>>;
    ImplicitWork& w = implicit_;
    const Vec3<S> n = options_.ground.normal.template cast<S>();
    for (int k = 0; k < nc_; ++k) {
      if (!reports_[static_cast<std::size_t>(k)].active) continue;
      const RowBlock J(jacobians_.data() + 6 * nv_ * k, 6, nv_);
      const double r = backend_.contact_radius(k);
      const Vec3<S> c(points_[3 * k], points_[3 * k + 1], points_[3 * k + 2]);
      const Vec3<S> v_c = J.template topRows<3>() * v_, omega = J.template bottomRows<3>() * v_;
      Vec3<AD> c_ad, v_ad, omega_ad;
      for (int i = 0; i < 3; ++i) {
        c_ad[i] = AD(c[i], 6, i);
        v_ad[i] = AD(v_c[i], 6, 3 + i);
        omega_ad[i] = AD(omega[i]);
      }
      const ContactReport<AD> f = contact_law<AD>(c_ad, v_ad, omega_ad, r, options_.ground, options_.contact_parameters);
      Mat3<S> dfdp, dfdv;
      for (int i = 0; i < 3; ++i) {
        dfdp.row(i) = f.force[i].derivatives().template head<3>().transpose();
        dfdv.row(i) = f.force[i].derivatives().template tail<3>().transpose();
      }
      w.Jw = J.template topRows<3>();
      w.Jw.noalias() -= skew<S>(-S(r) * n) * J.template bottomRows<3>();
      w.FJ.noalias() = (dfdv + S(h) * dfdp) * w.Jw;
      w.A.noalias() += w.Jw.transpose() * w.FJ;
      w.FJ.noalias() = dfdp * w.Jw;
      w.B.noalias() += w.Jw.transpose() * w.FJ;
    }
  }

  Backend backend_;
  SimulatorOptions options_;
  int nq_, nv_, ny_, nc_;
  VecX<S> q_, v_, q_start_, v_start_, q_stage_, v_stage_, q_eval_, tau_control_, tau_total_, tau_passive_;
  VecX<S> dq_[kMaxStages], dv_[kMaxStages], q_error_, v_error_;
  VecX<S> points_, jacobians_, contact_out_;
  std::vector<ContactReport<S>> reports_;
  JointStops<S> stops_;
  ImplicitWork implicit_;
  Controller controller_;
  PassiveForces passive_;
  S power_ = S(0);                  ///< (tau_control + tau_passive) . v of the last evaluation
  S stage_power_[kMaxStages] = {};  ///< power_ at each Runge-Kutta stage of the step
  double t_ = 0, step_ = 0, gravity_norm_ = 0;
  long control_ticks_ = 0;
  int closure_status_ = 0, closure_subsystem_ = -1;
  bool control_due_ = true;
  S work_ = S(0), energy_start_ = S(0), max_penetration_ = S(0);
  SimulationStatistics stats_;
  SoftLoops<S> soft_;                    ///< the continuation's work memory (sized when the backend has closure_constraints)
  std::vector<ContinuationSpan> spans_;  ///< reserved at set_state
  bool in_span_ = false, span_recorded_ = false, step_diverged_ = false;
  double closure_margin_ = 1;  ///< the last projection's worst relative pivot ratio
  int closure_worst_ = -1;     ///< and its sub-system
  double h_ = 0;                         ///< s: the step being taken
};

}  // namespace mbgen::sim
