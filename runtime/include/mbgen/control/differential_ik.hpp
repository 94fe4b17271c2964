#pragma once
// Differential inverse kinematics (resolved motion rate control) with a damped, weighted
// pseudo-inverse and secondary objectives in the null space of the primary tasks (DESIGN.md
// "Controller side"; thesis ch. 4, 5, 7).
//
// Coordinates. The controller solves for c = the velocity coordinates v (nv) of a tree, or the
// independent velocities y (ny, ModelStructure::independent_v order) of a model with closed loops, whose
// full velocity is v = T y (T from velocity_map): every Jacobian row J becomes J T, so the
// result keeps the loops closed to first order (Phi_q v = 0). Weights and velocity limits are
// per solved coordinate. A floating base is part of c: feet and torso tasks move it.
//
// One step, with W = diag(weights), D = W^-1/2, u = W^1/2 c (the weighted problem in unit metric):
//  1. primary: stack every task's rows J (m x nv) and desired velocity xd (m); A = J T D;
//     u1 = damped least-squares solution of A u = xd (damped_least_squares.hpp).
//  2. secondary, inside null(A) (N from the same SVD), minimising
//        1/2 |u2 - u_c|^2 + rho/2 |Bk D (u1 + u2) - k_des|^2
//     where u_c = -D T^T dP/dq is the steepest-descent velocity of the collision potential
//     (collision_potential.hpp; zero when no pair is within the activation distance; only those
//     pairs get Jacobian rows: the backend's self_distances_near) plus the joint-limit potential
//     (joint_limit_potential.hpp; zero when every limited joint is a margin away) and Bk the
//     angular rows of the centroidal momentum matrix (times T). The minimiser in closed form:
//        C = N (Bk D)^T (n x 3),  s = (I / rho + C^T C)^-1 (r - C^T u_c),  r = k_des - Bk D u1,
//        u2 = N u_c + C s,
//     a 3 x 3 solve whatever the robot. Per-axis weights w (AngularMomentumOptions::axis_weights)
//     scale Bk's rows and k_des by sqrt(w): rho w_i weighs axis i, and w_i = 0 drops it. Every term of u2 lies in range(N), so A u2 = 0 to
//     round-off: the secondary objectives never disturb the primary tasks. The first term keeps
//     the collision motion as it is when the momentum objective is off; rho weighs momentum
//     tracking against it (1/rho acts as the damping of the momentum objective).
//  3. c = D (u1 + u2); with velocity limits, c is scaled uniformly by the largest factor <= 1
//     that respects them (direction kept: primary and secondary are slowed together, the
//     null-space property holds). v = T c.
//
// The QP form (DifferentialIkOptions::qp, QpStepOptions; dense_qp.hpp) keeps the same objective
// and adds hard inequalities in u: each joint limit within its activation margin as
// v_i >= -(q_i - lower - margin) / h (velocity damper; the upper alike; v = T c reaches the dependent
// joints of the loops), each near pair as d + h_d d' >= d_min (the generated distance Jacobian), and
// the velocity limits |c_i| <= l_i (instead of the uniform scaling). The tasks are equalities:
//  stage 1, u = u1 + Z t with Z an orthonormal basis of null(A) (DampedLeastSquares::
//    null_space_basis): min over t of the secondary cost above (the momentum rows and the released
//    task rows as soft rows) subject to the inequalities. Without a binding inequality its
//    minimiser is the potential form's u2 (the same cost on the same subspace): the QP form is the
//    thesis' step plus the inequalities. The tasks hold exactly (to round-off) whenever some
//    null-space motion satisfies the inequalities;
//  stage 2, only when stage 1 is infeasible: min relaxation/2 |W (A u - xd)|^2 + 1/2 |u - u_ref|^2
//    over all u subject to the inequalities, W the tasks' weights (TaskSpec::weight), u_ref the
//    stage-1 optimum without inequalities. The tasks give the least the inequalities force, the
//    lightest task most (StepReport::tasks_relaxed). A weighted formulation throughout would never
//    achieve the tasks exactly; strict priorities everywhere would let an inequality the tasks
//    almost fix (a knee the feet and CoM nearly determine) demand an unbounded null-space speed.
// The joint-limit potential stays in the objective (it keeps an objective such as momentum
// tracking from pinning a joint at its stop, where the stop would then block the tasks).
// Released task rows (TaskTarget::released) leave the primary stack in both forms; the QP form
// tracks them softly (QpStepOptions::released_weight), the potential form leaves them free.
// QpStepOptions::smoothing adds smoothing/2 |u - u_last|^2 to both stages' objectives (u_last the
// last step's command): the steps' velocity then changes gradually where an active set or a
// released row changes (off by default; with it the QP form's optimum is no longer the potential
// form's when nothing binds).
//
// Backends. The step reads the robot through a backend (sim/backend.hpp: task_kinematics,
// velocity_map, self_distances_near, the sizes): BasicDifferentialIk<NAME::Backend> runs on the
// generated functions, DifferentialIk<S> on the generic runtime (GenericBackend<S> over a Model,
// its frames the tasks', its pairs the collision model's). The same step, the same arithmetic
// after the backend's outputs: generated equals generic to round-off (test_differential_ik).
// A task's frame must be one of the backend's frames (a generated backend's: the scene's
// `jacobians:`).
//
// Allocation: the constructor sizes everything from the backend and the task list; step() does
// not allocate and does not throw (tests/test_differential_ik.cpp checks it under a malloc guard).
// Errors in the configuration throw std::invalid_argument at construction, naming what is wrong.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Cholesky>

#include "mbgen/control/collision_potential.hpp"
#include "mbgen/control/damped_least_squares.hpp"
#include "mbgen/control/dense_qp.hpp"
#include "mbgen/control/joint_limit_potential.hpp"
#include "mbgen/control/task.hpp"
#include "mbgen/sim/backend.hpp"

namespace mbgen::control {

struct AngularMomentumOptions {
  bool enabled = false;
  double weight = 1e4;  ///< rho: weight of |k - k_des|^2 against |u2 - u_c|^2 (kg m^2/s)^-2
  /// Per world axis (x, y, z), >= 0, multiplying rho: (0, 0, 1) tracks the vertical component
  /// alone (a walker's arms compensating its legs' yaw momentum), leaving pitch and roll free.
  std::array<double, 3> axis_weights{1.0, 1.0, 1.0};
};

/// The step as a QP (control/dense_qp.hpp): the same objectives, with joint position limits, pair
/// distances and velocity limits as hard inequalities (velocity-damper form). Off: the potential
/// form above, the thesis' own.
struct QpStepOptions {
  bool enabled = false;
  /// s: each limit of DifferentialIkOptions::joint_limits within its activation margin becomes
  /// v_i >= -(q_i - lower - limit_margin) / limit_horizon (the upper one alike): the margin may
  /// shrink by at most dt / limit_horizon of itself per step of dt, so it stays >= limit_margin
  /// for dt <= limit_horizon (to first order: exactly for a joint that is an independent coordinate).
  double limit_horizon = 0.05;
  double limit_margin = 0.0;  ///< rad or m: kept from each limit
  /// s: each pair within collision.activation_distance (collision avoidance on) becomes
  /// d + collision_horizon * d' >= min_distance, d' from the generated distance Jacobian.
  double collision_horizon = 0.05;
  double min_distance = 0.005;  ///< m
  /// When the inequalities leave no velocity that achieves every task exactly, the tasks' rows
  /// enter the objective with this weight (times TaskSpec::weight) against the secondary
  /// objectives' 1: the tasks give as little as the inequalities force, in proportion to 1/weight.
  double relaxation_weight = 1e6;
  /// Weight of a released task row (TaskTarget::released) in the secondary objective.
  double released_weight = 100.0;
  /// Weight of |u - u_last|^2 in the objective (u the weighted coordinates, u_last the last step's
  /// command; zero before the first step, after a failed one and after restart()). 0: off, and the
  /// step is the potential form's wherever no inequality binds. The velocity of a QP step jumps
  /// whenever its active set or its tasks' rows change (an inequality reached, a row released or
  /// taken back); at 1 kHz a jump is an acceleration spike, a torque spike in the ground's wrench.
  /// With weight w against the objective's own unit weight on |u2 - u_c|^2, a step closes about
  /// 1 / (1 + w) of the gap between the last command and the new optimum: a first-order lag of
  /// about w steps where the other objectives are weak, less where they are strong (momentum
  /// tracking's 1e4). The tasks stay exact: the term lives in the null space (stage 1), and in
  /// stage 2 beside the relaxed tasks.
  double smoothing = 0.0;
};

struct DifferentialIkOptions {
  DampingOptions damping{0.0, 1e-2, 1e-2, 1e-10};  ///< primary stack (singular region 0.01, max damping 0.01)
  std::vector<double> weights;          ///< per solved coordinate, > 0; empty: all 1
  std::vector<double> velocity_limits;  ///< per solved coordinate, > 0 (inf allowed); empty: none
  /// Self-collision avoidance: needs the backend's pairs (a collision model for DifferentialIk).
  bool collision_avoidance = false;
  CollisionPotentialOptions collision;
  /// Joint position limits (joint_limit_potential.hpp; joint_position_limits(model) gives the
  /// description's): their potential is descended with the collision potential's, in the null
  /// space. Empty limits: off.
  JointLimitOptions joint_limits;
  AngularMomentumOptions angular_momentum;
  /// The QP form: joint limits, distances and velocity limits as hard inequalities (with it, the
  /// joint limits are constraints, not the potential).
  QpStepOptions qp;
};

/// What a step did (no exceptions in the step: a failure is reported here, qd is then zero).
struct StepReport {
  bool ok = false;          ///< false if the primary Jacobian, a target or the result was not finite
  int rank = 0;             ///< numerical rank of the weighted primary Jacobian
  double smallest_singular_value = 0;
  int active_pairs = 0;     ///< collision pairs within the activation distance
  int near_pairs = 0;       ///< pairs closer than it: those with Jacobian rows (active_pairs but for NaN distances)
  int active_limits = 0;    ///< joint limits within their activation margin
  double limit_scale = 1;   ///< factor applied to respect the velocity limits (1: none active)
  // The QP form (QpStepOptions):
  QpStatus qp_status = QpStatus::solved;  ///< of the last QP solved (ok is false unless solved)
  int inequalities = 0;         ///< rows given to the QP: limits within their margin, near pairs, velocity limits
  int active_inequalities = 0;  ///< of them, active at the solution
  /// The QP's active-set changes (rows added, dropped). The last step's active rows start the
  /// step's QP (a warm start) and are not counted: a step whose active set did not change has 0.
  int qp_iterations = 0;
  bool tasks_relaxed = false;   ///< no exact solution within the inequalities: the tasks were weighted
};

template <typename Backend> class BasicDifferentialIk {
 public:
  using S = typename Backend::Scalar;

  /// tasks: the primary stack (at least one), each frame one of the backend's frames. The
  /// backend is kept (a generated one is an empty struct; GenericBackend holds its Model by
  /// reference).
  BasicDifferentialIk(Backend backend, const std::vector<TaskSpec>& tasks, const DifferentialIkOptions& options = {})
      : backend_(std::move(backend)), options_(options), nv_(backend_.nv()), loops_(backend_.ny() < backend_.nv()),
        nc_(backend_.ny()), nf_(backend_.num_frames()), m_(count_rows(tasks)), dls_(m_, nc_, options.damping) {
    int row = 0;
    for (const TaskSpec& spec : tasks) {
      for (const Task& t : tasks_)
        if (t.spec.name == spec.name) throw std::invalid_argument("DifferentialIk: two tasks named '" + spec.name + "'");
      Task task;
      task.spec = spec;
      task.row = row;
      check_gain(spec);
      if (spec.kind != TaskKind::CenterOfMass) {
        task.slot = -1;
        std::string frames;
        for (int k = 0; k < nf_; ++k) {
          if (spec.frame == backend_.frame_name(k)) task.slot = k;
          frames += (k ? ", " : "") + std::string(backend_.frame_name(k));
        }
        if (task.slot < 0)
          throw std::invalid_argument("task '" + spec.name + "': frame '" + spec.frame + "' is not among the backend's frames (" + frames +
                                      "): generate it (the scene's `jacobians:`)");
      }
      tasks_.push_back(task);
      row += task_rows(spec.kind);
    }
    targets_.assign(tasks_.size(), TaskTarget<S>{});
    scale_ = VecX<S>::Ones(nc_);
    limits_ = VecX<S>::Constant(nc_, std::numeric_limits<S>::infinity());
    if (!options.weights.empty()) {
      if (static_cast<int>(options.weights.size()) != nc_) throw std::invalid_argument(size_message("weights", options.weights.size()));
      for (int i = 0; i < nc_; ++i) {
        const double w = options.weights[static_cast<std::size_t>(i)];
        if (!(w > 0) || !std::isfinite(w))
          throw std::invalid_argument("DifferentialIk: weights[" + std::to_string(i) + "] = " + std::to_string(w) + " must be finite and > 0");
        scale_[i] = S(1) / std::sqrt(S(w));
      }
    }
    if (!options.velocity_limits.empty()) {
      if (static_cast<int>(options.velocity_limits.size()) != nc_)
        throw std::invalid_argument(size_message("velocity_limits", options.velocity_limits.size()));
      for (int i = 0; i < nc_; ++i) {
        const double l = options.velocity_limits[static_cast<std::size_t>(i)];
        if (!(l > 0)) throw std::invalid_argument("DifferentialIk: velocity_limits[" + std::to_string(i) + "] = " + std::to_string(l) + " must be > 0");
        limits_[i] = S(l);
      }
    }
    check(options.joint_limits, backend_.nq(), nv_);
    pairs_ = 0;
    if (options.collision_avoidance) {
      check(options.collision);
      pairs_ = backend_.num_distance_pairs();
    }
    qp_ = options.qp.enabled;
    // In the QP form the joint limits are inequalities and, as in the potential form, a potential
    // descended in the objective: without it an objective (momentum tracking) pins a joint at its
    // stop, where the stop then blocks the tasks.
    repulsion_ = pairs_ > 0 || !options.joint_limits.limits.empty();
    if (qp_) check_qp(options, tasks);
    if (options.angular_momentum.enabled && (!(options.angular_momentum.weight > 0) || !std::isfinite(options.angular_momentum.weight)))
      throw std::invalid_argument("DifferentialIk: angular_momentum.weight must be finite and > 0, got " +
                                  std::to_string(options.angular_momentum.weight));
    for (int i = 0; i < 3; ++i) {
      const double w = options.angular_momentum.axis_weights[static_cast<std::size_t>(i)];
      if (!(w >= 0) || !std::isfinite(w))
        throw std::invalid_argument("DifferentialIk: angular_momentum.axis_weights[" + std::to_string(i) + "] = " + std::to_string(w) +
                                    " must be finite and >= 0");
      axis_scale_[i] = std::sqrt(S(w));
    }
    mass_ = S(backend_.total_mass());
    X_WF_.assign(static_cast<std::size_t>(12 * std::max(nf_, 1)), S(0));
    frame_J_.assign(static_cast<std::size_t>(6 * nv_ * std::max(nf_, 1)), S(0));
    Ag_ = RowMatX::Zero(6, nv_);
    distance_.assign(static_cast<std::size_t>(std::max(pairs_, 1)), S(0));
    near_.assign(static_cast<std::size_t>(std::max(pairs_, 1)), 0);
    normal_.assign(static_cast<std::size_t>(3 * std::max(pairs_, 1)), S(0));
    witness_.assign(static_cast<std::size_t>(6 * std::max(pairs_, 1)), S(0));
    distance_J_ = RowMatX::Zero(std::max(pairs_, 1), nv_);
    J_ = MatX<S>::Zero(m_, nv_);
    xd_ = VecX<S>::Zero(m_);
    A_ = MatX<S>::Zero(m_, nc_);
    T_ = RowMatX::Zero(nv_, loops_ ? nc_ : 0);
    independent_column_.assign(static_cast<std::size_t>(nv_), -1);
    if (loops_)
      for (int c = 0; c < nc_; ++c) independent_column_[static_cast<std::size_t>(backend_.independent_v_index()[c])] = c;
    t_row_.assign(static_cast<std::size_t>(T_.size()), 0);
    t_col_.assign(static_cast<std::size_t>(T_.size()), 0);
    t_value_.assign(static_cast<std::size_t>(T_.size()), S(0));
    Jcom_ = Mat3X<S>::Zero(3, nv_);
    gradient_ = VecX<S>::Zero(nv_);
    gradient_c_ = VecX<S>::Zero(nc_);
    Bk_ = Mat3X<S>::Zero(3, nc_);
    to_null_ = Eigen::Matrix<S, Eigen::Dynamic, 4, Eigen::RowMajor>::Zero(nc_, 4);
    from_null_ = Eigen::Matrix<S, Eigen::Dynamic, 2, Eigen::RowMajor>::Zero(nc_, 2);
    u1_ = VecX<S>::Zero(nc_);
    u2_ = VecX<S>::Zero(nc_);
    u_last_ = VecX<S>::Zero(nc_);
    smooth_offset_ = VecX<S>::Zero(nc_);
    uc_ = VecX<S>::Zero(nc_);
    c_ = VecX<S>::Zero(nc_);
    secondary_ = VecX<S>::Zero(nc_);
    collision_ = VecX<S>::Zero(nc_);
    row_weight_ = VecX<S>::Ones(m_);
    for (const Task& t : tasks_) row_weight_.segment(t.row, t.rows()).setConstant(std::sqrt(S(t.spec.weight)));
    if (qp_) {
      const int limits = static_cast<int>(options.joint_limits.limits.size());
      const int velocity_rows = options.velocity_limits.empty() ? 0 : 2 * nc_;
      max_inequalities_ = 2 * limits + pairs_ + velocity_rows;
      solver_ = DenseQp<S>(nc_, 0, std::max(max_inequalities_, 1));
      Z_ = MatX<S>::Zero(nc_, nc_);
      unit_column_.assign(static_cast<std::size_t>(std::max(max_inequalities_, 1)), 0);
      unit_coefficient_.assign(static_cast<std::size_t>(std::max(max_inequalities_, 1)), S(0));
      unit_bound_.assign(static_cast<std::size_t>(std::max(max_inequalities_, 1)), S(0));
      unit_key_.assign(static_cast<std::size_t>(std::max(max_inequalities_, 1)), 0);
      row_key_.assign(static_cast<std::size_t>(std::max(max_inequalities_, 1)), 0);
      row_of_key_.assign(static_cast<std::size_t>(std::max(max_inequalities_, 1)), -1);
      active_key_.assign(static_cast<std::size_t>(std::max(max_inequalities_, 1)), 0);
      start_row_.assign(static_cast<std::size_t>(std::max(max_inequalities_, 1)), -1);
      Cu_ = MatX<S>::Zero(std::max(max_inequalities_, 1), nc_);
      Ct_ = MatX<S>::Zero(std::max(max_inequalities_, 1), nc_);
      cu_ = VecX<S>::Zero(std::max(max_inequalities_, 1));
      ct_ = VecX<S>::Zero(std::max(max_inequalities_, 1));
      distance_T_ = RowMatX::Zero(std::max(pairs_, 1), nc_);
      soft_ = MatX<S>::Zero(3 + m_, nc_);
      soft_target_ = VecX<S>::Zero(3 + m_);
      soft_residual_ = VecX<S>::Zero(3 + m_);
      soft_Z_ = MatX<S>::Zero(3 + m_, nc_);
      Gq_ = MatX<S>::Zero(nc_, nc_);
      aq_ = VecX<S>::Zero(nc_);
      Aw_ = MatX<S>::Zero(m_, nc_);
      xw_ = VecX<S>::Zero(m_);
      no_rows_ = MatX<S>::Zero(0, nc_);
      no_values_ = VecX<S>::Zero(0);
    }
  }

  int num_tasks() const { return static_cast<int>(tasks_.size()); }
  int primary_rows() const { return m_; }
  /// Number of solved coordinates: nv for a tree, ny (independent velocities) with loops.
  int num_coordinates() const { return nc_; }
  const Task& task(int i) const { return tasks_[static_cast<std::size_t>(i)]; }
  /// The index of the task named `name`; throws std::out_of_range naming it if there is none.
  int task_index(const std::string& name) const {
    for (std::size_t i = 0; i < tasks_.size(); ++i)
      if (tasks_[i].spec.name == name) return static_cast<int>(i);
    throw std::out_of_range("DifferentialIk: no task named '" + name + "'");
  }
  /// The reference of task i: set it before step().
  TaskTarget<S>& target(int i) { return targets_[static_cast<std::size_t>(i)]; }
  /// Desired centroidal angular momentum (world axes, about the CoM) for the momentum objective.
  Vec3<S> angular_momentum_target = Vec3<S>::Zero();

  /// Joint velocities v (nv; T y with loops) for configuration q (nq, loops closed). Returns what
  /// happened; on !ok, v is zero.
  /// QpStepOptions::smoothing pulls each step toward the last one's command; after a pause (the
  /// robot stopped, or moved by something else) that command is stale: restart() forgets it, the
  /// next step is smoothed toward rest.
  void restart() { u_last_.setZero(); }
  StepReport step(const ConstVecRef<S>& q, Eigen::Ref<VecX<S>> v) {
    StepReport report;
    backend_.task_kinematics(q.data(), X_WF_.data(), frame_J_.data(), com_.data(), Ag_.data());
    Jcom_ = Ag_.template topRows<3>() / mass_;
    for (std::size_t i = 0; i < tasks_.size(); ++i) write_task_rows(tasks_[i], targets_[i]);
    if (loops_) {
      backend_.velocity_map(q.data(), T_.data());
      gather_velocity_map_entries();
      times_velocity_map(J_, A_);
    } else {
      A_ = J_;
    }
    A_.array().rowwise() *= scale_.transpose().array();
    release_rows();
    if (!xd_.allFinite() || !dls_.compute(A_)) {
      v.setZero();
      u_last_.setZero();
      return report;
    }
    report.ok = true;
    report.rank = dls_.rank();
    report.smallest_singular_value = static_cast<double>(dls_.smallest_singular_value());
    dls_.solve(xd_, u1_);

    // Collision and joint limits: u_c = -D T^T dP/dq for P the sum of their potentials, projected
    // into the null space (below, with the momentum rows).
    uc_.setZero();
    if (repulsion_) {
      gradient_.setZero();
      if (pairs_ > 0) {
        // The near set at the activation distance: only the pairs closer than it (the active ones)
        // get witnesses and Jacobian rows (compact); bounding spheres spare the far pairs' SSV calls.
        int num_near = 0;
        backend_.self_distances_near(q.data(), S(options_.collision.activation_distance), distance_.data(), near_.data(), &num_near,
                                     normal_.data(), witness_.data(), distance_J_.data());
        report.near_pairs = num_near;
        report.active_pairs =
            collision_potential_gradient<S>(num_near, near_.data(), distance_.data(), distance_J_, options_.collision, gradient_);
      }
      report.active_limits = add_joint_limit_gradient<S>(q.data(), options_.joint_limits, gradient_);
      to_coordinates(gradient_, gradient_c_);
      uc_ = -scale_.cwiseProduct(gradient_c_);
    }
    if (qp_) {
      if (!qp_secondary(q.data(), report.near_pairs, report)) {
        v.setZero();
        u_last_.setZero();
        report.ok = false;
        return report;
      }
    } else if (options_.angular_momentum.enabled) {
      momentum_rows();
      // In the null space's coordinates (N = P^T D0 P, damped_least_squares.hpp): t_c = D0 P u_c and
      // t_B = D0 P (Bk D)^T, one pass over the reflectors for the four columns. With C = N (Bk D)^T,
      // C^T C = t_B^T t_B and C^T u_c = t_B^T t_c, and u2 = N u_c + C s = P^T (t_c + t_B s).
      to_null_.col(0) = uc_;
      to_null_.template rightCols<3>() = Bk_.transpose();
      dls_.to_null_space(to_null_);
      const Vec3<S> r = axis_scale_.cwiseProduct(angular_momentum_target) - Bk_ * u1_;
      Mat3<S> M;
      M.noalias() = to_null_.template rightCols<3>().transpose() * to_null_.template rightCols<3>();
      M.diagonal().array() += S(1) / S(options_.angular_momentum.weight);
      const Vec3<S> s = Eigen::LLT<Mat3<S>>(M).solve(r - to_null_.template rightCols<3>().transpose() * to_null_.col(0));
      from_null_.col(0) = to_null_.col(0);
      from_null_.col(1).noalias() = to_null_.template rightCols<3>() * s;
      from_null_.col(1) += to_null_.col(0);
      dls_.from_null_space(from_null_);  // [N u_c, u2]
      uc_ = from_null_.col(0);
      u2_ = from_null_.col(1);
    } else {
      if (repulsion_) dls_.project_to_null(uc_);
      u2_ = uc_;
    }
    secondary_ = scale_.cwiseProduct(u2_);
    collision_ = scale_.cwiseProduct(uc_);
    c_ = scale_.cwiseProduct(u1_ + u2_);  // the QP's u1 + u2 is its solution (qp_secondary)
    if (!c_.allFinite()) {  // e.g. a distance that came out NaN: refuse rather than command it
      v.setZero();
      u_last_.setZero();
      report.ok = false;
      return report;
    }
    if (qp_) u_last_ = u1_ + u2_;  // the command (the QP form has no limit_scale)
    S limit_scale = S(1);
    for (int i = 0; i < nc_ && !qp_; ++i)  // the QP form has them as inequalities
      if (std::abs(c_[i]) * limit_scale > limits_[i]) limit_scale = limits_[i] / std::abs(c_[i]);
    c_ *= limit_scale;
    report.limit_scale = static_cast<double>(limit_scale);
    if (loops_) {
      v.setZero();
      for (int k = 0; k < t_count_; ++k) {
        const std::size_t i = static_cast<std::size_t>(k);
        v[t_row_[i]] += t_value_[i] * c_[t_col_[i]];
      }
    } else {
      v = c_;
    }
    return report;
  }

  // Results of the last step (for logging and tests).
  const MatX<S>& primary_jacobian() const { return J_; }          ///< m x nv, world axes
  const VecX<S>& primary_velocity() const { return xd_; }         ///< m: desired task velocity incl. feedback
  /// nv x ny (loops only; empty for a tree).
  const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& velocity_map() const { return T_; }
  const VecX<S>& coordinates_velocity() const { return c_; }      ///< nc: the solved velocity (after limits)
  /// nc: the secondary part D u2 of the solved velocity (before limits): in null(J T).
  const VecX<S>& secondary_velocity() const { return secondary_; }
  /// nc: D N u_c (before limits), the descent of the collision and joint-limit potentials.
  const VecX<S>& collision_velocity() const { return collision_; }
  const VecX<S>& collision_gradient() const { return gradient_; }  ///< nv: dP/dq, both potentials
  /// The distances of the last step's pairs (collision avoidance on; else empty): exact for the
  /// pairs within the activation distance, a lower bound at least the activation distance for the
  /// others (self_distances_near).
  const S* distances() const { return distance_.data(); }
  int num_pairs() const { return pairs_; }
  const Vec3<S>& center_of_mass() const { return com_; }          ///< of the last step's q
  /// Centroidal momentum matrix of the last step's q (6 x nv, world axes, about the CoM).
  const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& centroidal_momentum_matrix() const { return Ag_; }
  Backend& backend() { return backend_; }

 private:
  using RowMatX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  using FrameJacobian = Eigen::Map<const Eigen::Matrix<S, 6, Eigen::Dynamic, Eigen::RowMajor>>;

  static int count_rows(const std::vector<TaskSpec>& tasks) {
    if (tasks.empty()) throw std::invalid_argument("DifferentialIk: needs at least one primary task");
    int m = 0;
    for (const TaskSpec& t : tasks) m += task_rows(t.kind);
    return m;
  }
  static void check_gain(const TaskSpec& spec) {
    if (!(spec.gain >= 0) || !std::isfinite(spec.gain))
      throw std::invalid_argument("task '" + spec.name + "': gain must be finite and >= 0, got " + std::to_string(spec.gain));
  }
  std::string size_message(const char* what, std::size_t got) const {
    return std::string("DifferentialIk: ") + what + " has " + std::to_string(got) + " entries, expected " + std::to_string(nc_) +
           (loops_ ? " (one per independent velocity: the model has closed loops)" : " (one per velocity coordinate, nv)");
  }
  /// The task's Jacobian rows into J_ and its desired velocity into xd_ (task.hpp's law).
  void write_task_rows(const Task& task, const TaskTarget<S>& target) {
    const S gain(task.spec.gain);
    if (task.spec.kind == TaskKind::CenterOfMass) {
      J_.middleRows(task.row, 3) = Jcom_;
      xd_.template segment<3>(task.row) = target.velocity.template head<3>() + gain * (target.position - com_);
      return;
    }
    const S* X = X_WF_.data() + 12 * task.slot;
    Mat3<S> R;
    Vec3<S> p;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) R(r, c) = X[4 * r + c];
      p[r] = X[4 * r + 3];
    }
    const FrameJacobian Jf(frame_J_.data() + 6 * nv_ * task.slot, 6, nv_);
    const Vec3<S> linear = target.velocity.template head<3>() + gain * (target.position - p);
    const Vec3<S> angular = target.velocity.template tail<3>() + gain * orientation_error<S>(target.rotation, R);
    switch (task.spec.kind) {
      case TaskKind::FramePose:
        J_.middleRows(task.row, 6) = Jf;
        xd_.template segment<3>(task.row) = linear;
        xd_.template segment<3>(task.row + 3) = angular;
        break;
      case TaskKind::FramePosition:
        J_.middleRows(task.row, 3) = Jf.template topRows<3>();
        xd_.template segment<3>(task.row) = linear;
        break;
      case TaskKind::FrameOrientation:
        J_.middleRows(task.row, 3) = Jf.template bottomRows<3>();
        xd_.template segment<3>(task.row) = angular;
        break;
      case TaskKind::CenterOfMass: break;
    }
  }
  /// Bk_ = the angular rows of the centroidal momentum matrix times T D, each scaled by the square
  /// root of its axis weight.
  void momentum_rows() {
    if (loops_) {
      times_velocity_map(Ag_.template bottomRows<3>(), Bk_);
    } else {
      Bk_ = Ag_.template bottomRows<3>();
    }
    Bk_.array().rowwise() *= scale_.transpose().array();
    Bk_.array().colwise() *= axis_scale_.array();  // per-axis weights: rows scaled by their square roots
  }
  /// The targets' released rows leave the primary stack (A_, J_ and xd_ zeroed there); the QP form
  /// keeps each as a soft row of weight released_weight (soft_, from row 0).
  void release_rows() {
    num_soft_ = 0;
    const S w = qp_ ? std::sqrt(S(options_.qp.released_weight)) : S(0);
    for (std::size_t i = 0; i < tasks_.size(); ++i) {
      const Task& task = tasks_[i];
      for (int r = 0; r < task.rows(); ++r) {
        if (!targets_[i].released[static_cast<std::size_t>(r)]) continue;
        const int row = task.row + r;
        if (qp_) {
          soft_.row(num_soft_) = w * A_.row(row);
          soft_target_[num_soft_] = w * xd_[row];
          ++num_soft_;
        }
        A_.row(row).setZero();
        J_.row(row).setZero();
        xd_[row] = S(0);
      }
    }
  }
  void check_qp(const DifferentialIkOptions& o, const std::vector<TaskSpec>& tasks) const {
    const QpStepOptions& qp = o.qp;
    const auto positive = [](double x) { return x > 0 && std::isfinite(x); };
    if (!positive(qp.limit_horizon) || !positive(qp.collision_horizon) || !positive(qp.relaxation_weight) || !positive(qp.released_weight))
      throw std::invalid_argument("DifferentialIk: qp.limit_horizon, collision_horizon, relaxation_weight and released_weight must be finite and > 0");
    if (!(qp.smoothing >= 0) || !std::isfinite(qp.smoothing))
      throw std::invalid_argument("DifferentialIk: qp.smoothing must be finite and >= 0, got " + std::to_string(qp.smoothing));
    if (!(qp.limit_margin >= 0) || !std::isfinite(qp.limit_margin) || !(qp.min_distance >= 0) || !std::isfinite(qp.min_distance))
      throw std::invalid_argument("DifferentialIk: qp.limit_margin and qp.min_distance must be finite and >= 0");
    if (!o.joint_limits.limits.empty() && !(qp.limit_margin < o.joint_limits.activation))
      throw std::invalid_argument("DifferentialIk: qp.limit_margin (" + std::to_string(qp.limit_margin) +
                                  ") must be below joint_limits.activation (" + std::to_string(o.joint_limits.activation) +
                                  "): a limit gets its inequality only within the activation margin");
    if (o.collision_avoidance && !(qp.min_distance < o.collision.activation_distance))
      throw std::invalid_argument("DifferentialIk: qp.min_distance must be below collision.activation_distance");
    for (const TaskSpec& t : tasks)
      if (!positive(t.weight)) throw std::invalid_argument("task '" + t.name + "': weight must be finite and > 0, got " + std::to_string(t.weight));
  }
  /// The QP form's secondary step (after u1_ and uc_): writes u1_ + u2_ = the solution. Rows in the
  /// weighted coordinates u (c = D u): Cu u >= cu for the inequalities; the soft rows (released
  /// task rows, then the momentum rows times sqrt(rho)) and |u2 - u_c|^2 as the objective.
  /// First in the null space of the primary stack, u = u1 + Z t (the tasks exact); if that is
  /// infeasible, over all of u with the tasks weighted (tasks_relaxed).
  bool qp_secondary(const S* q, int num_near, StepReport& report) {
    if (options_.angular_momentum.enabled) {
      momentum_rows();
      const S root_rho = std::sqrt(S(options_.angular_momentum.weight));
      soft_.middleRows(num_soft_, 3) = root_rho * Bk_;
      soft_target_.segment(num_soft_, 3) = root_rho * axis_scale_.cwiseProduct(angular_momentum_target);
    }
    const int soft = num_soft_ + (options_.angular_momentum.enabled ? 3 : 0);
    const int mi = inequality_rows(q, num_near);
    const int general = general_rows_;  // the dense rows; after them the unit rows (inequality_rows)
    report.inequalities = mi;
    // Stage 1: t in the null space's coordinates. G = I + (S Z)^T (S Z), a = -Z^T u_c + (S Z)^T (S u1 - s).
    const int k = dls_.null_space_basis(Z_);
    const auto Z = Z_.leftCols(k);
    soft_residual_.head(soft).noalias() = soft_.topRows(soft) * u1_;
    soft_residual_.head(soft) -= soft_target_.head(soft);  // S u1 - s
    QpStatus status = QpStatus::infeasible;
    if (k > 0) {
      soft_Z_.topLeftCorner(soft, k).noalias() = soft_.topRows(soft) * Z;
      auto G = Gq_.topLeftCorner(k, k);
      G.setIdentity();
      G.noalias() += soft_Z_.topLeftCorner(soft, k).transpose() * soft_Z_.topLeftCorner(soft, k);
      aq_.head(k).noalias() = soft_Z_.topLeftCorner(soft, k).transpose() * soft_residual_.head(soft);
      aq_.head(k).noalias() -= Z.transpose() * uc_;
      if (const S w_s(options_.qp.smoothing); w_s > S(0)) {  // + w_s/2 |u1 + Z t - u_last|^2 (Z orthonormal: G gets w_s I)
        G.diagonal().array() += w_s;
        smooth_offset_ = u1_ - u_last_;
        aq_.head(k).noalias() += w_s * (Z.transpose() * smooth_offset_);
      }
      Ct_.topLeftCorner(general, k).noalias() = Cu_.topRows(general) * Z;
      ct_.head(general) = cu_.head(general);
      ct_.head(general).noalias() -= Cu_.topRows(general) * u1_;
      // A unit row a e_i: its null-space row is a Z(i, :) and its value at u1 is a u1_i, no product.
      for (int r = general; r < mi; ++r) {
        const std::size_t j = static_cast<std::size_t>(r - general);
        Ct_.row(r).head(k) = unit_coefficient_[j] * Z.row(unit_column_[j]);
        ct_[r] = cu_[r] - unit_coefficient_[j] * u1_[unit_column_[j]];
      }
      // Warm start: the last step's active rows, by what they are (row_key_), at their new indices.
      for (int j = 0; j < num_active_keys_; ++j) start_row_[static_cast<std::size_t>(j)] = row_of_key_[static_cast<std::size_t>(active_key_[static_cast<std::size_t>(j)])];
      status = solver_.solve(G, aq_.head(k), no_rows_.leftCols(k), no_values_, Ct_.topLeftCorner(mi, k), ct_.head(mi), start_row_.data(),
                             num_active_keys_);
      num_active_keys_ = 0;
      if (status == QpStatus::solved) {
        u2_.noalias() = Z * solver_.solution();
        num_active_keys_ = solver_.num_active_inequalities();
        for (int j = 0; j < num_active_keys_; ++j) active_key_[static_cast<std::size_t>(j)] = row_key_[static_cast<std::size_t>(solver_.active_inequality(j))];
      }
    } else {
      // No null space: u1 is the only velocity that achieves the tasks; it is feasible or not.
      fill_unit_rows(mi);
      num_active_keys_ = 0;
      ct_.head(mi).noalias() = Cu_.topRows(mi) * u1_;
      status = mi == 0 || (ct_.head(mi) - cu_.head(mi)).minCoeff() >= -S(1e-12) * (S(1) + cu_.head(mi).norm()) ? QpStatus::solved
                                                                                                                 : QpStatus::infeasible;
      u2_.setZero();
    }
    // The collision descent as the potential form has it, N u_c (for collision_velocity()).
    if (repulsion_) dls_.project_to_null(uc_);
    report.tasks_relaxed = false;
    if (status == QpStatus::infeasible) {
      // Stage 2: min relaxation/2 |W (A u - xd)|^2 + 1/2 |u - u_ref|^2, u_ref the stage-1 optimum
      // without the inequalities (the tasks exact, the secondary objectives met as well as the
      // null space allows). The secondary objectives enter only through u_ref: were their rows in
      // this objective, an unreachable momentum target would pull on the tasks themselves.
      report.tasks_relaxed = true;
      u2_.setZero();
      if (k > 0) {
        if (solver_.solve(Gq_.topLeftCorner(k, k), aq_.head(k), no_rows_.leftCols(k), no_values_, Ct_.topLeftCorner(0, k), ct_.head(0)) !=
            QpStatus::solved) {
          report.qp_status = solver_.status();
          return false;
        }
        u2_.noalias() = Z * solver_.solution();
      }
      const S w = std::sqrt(S(options_.qp.relaxation_weight));
      Aw_ = A_;
      Aw_.array().colwise() *= (w * row_weight_).array();
      xw_ = (w * row_weight_).cwiseProduct(xd_);
      Gq_.setIdentity();
      Gq_.noalias() += Aw_.transpose() * Aw_;
      aq_ = -(u1_ + u2_);
      aq_.noalias() -= Aw_.transpose() * xw_;
      if (const S w_s(options_.qp.smoothing); w_s > S(0)) {  // + w_s/2 |u - u_last|^2
        Gq_.diagonal().array() += w_s;
        aq_ -= w_s * u_last_;
      }
      fill_unit_rows(mi);
      status = solver_.solve(Gq_, aq_, no_rows_, no_values_, Cu_.topRows(mi), cu_.head(mi));
      if (status == QpStatus::solved) u2_ = solver_.solution() - u1_;
    }
    report.qp_status = status;
    report.active_inequalities = status == QpStatus::solved ? solver_.num_active_inequalities() : 0;
    report.qp_iterations = solver_.iterations();
    return status == QpStatus::solved;
  }
  /// Cu_ u >= cu_ (weighted coordinates u, c = D u): the limits within their activation margin,
  /// the near pairs, the velocity limits. Returns the number of rows. The dense rows (a dependent
  /// joint's limit through T, the near pairs) come first, general_rows_ of them, in Cu_; then the
  /// unit rows a e_i (an independent coordinate's limit, a velocity limit), kept as (i, a) only:
  /// in the null space each is a copy of a row of Z, not a row times Z (Lola along the bench's
  /// motion: 107-112 rows, about 32 of them dense). Cu_ gets them only where a stage needs all
  /// rows (fill_unit_rows). cu_ holds every row's bound, in that order.
  int inequality_rows(const S* q, int num_near) {
    const QpStepOptions& o = options_.qp;
    for (int r = 0; r < num_rows_; ++r) row_of_key_[static_cast<std::size_t>(row_key_[static_cast<std::size_t>(r)])] = -1;
    int mi = 0, units = 0;
    // Each row's key says what it is, whichever rows come and go: limit l's side s is 2 l + s,
    // pair p is 2 L + p, coordinate i's velocity limit from above/below 2 L + P + 2 i + 0/1.
    const int num_limits = static_cast<int>(options_.joint_limits.limits.size());
    const auto unit = [&](int column, S coefficient, S bound, int key) {
      const std::size_t j = static_cast<std::size_t>(units++);
      unit_column_[j] = column;
      unit_coefficient_[j] = coefficient;
      unit_bound_[j] = bound;
      unit_key_[j] = key;
    };
    const S activation(options_.joint_limits.activation), margin(o.limit_margin), h(o.limit_horizon);
    for (int li = 0; li < num_limits; ++li) {
      const JointLimit& l = options_.joint_limits.limits[static_cast<std::size_t>(li)];
      const S x = q[l.q_index];
      const S below = x - S(l.lower), above = S(l.upper) - x;
      for (int side = 0; side < 2; ++side) {
        const S gap = side == 0 ? below : above;
        if (!(gap < activation)) continue;
        const S sign = side == 0 ? S(1) : S(-1);
        const S bound = -(gap - margin) / h;
        // An independent coordinate's row of T is its unit row (the backend's contract).
        const int column = loops_ ? independent_column_[static_cast<std::size_t>(l.v_index)] : l.v_index;
        if (column >= 0) {
          unit(column, sign * (loops_ ? T_(l.v_index, column) : S(1)) * scale_[column], bound, 2 * li + side);
          continue;
        }
        Cu_.row(mi) = sign * T_.row(l.v_index).cwiseProduct(scale_.transpose());
        cu_[mi] = bound;
        row_key_[static_cast<std::size_t>(mi)] = 2 * li + side;
        ++mi;
      }
    }
    if (num_near > 0) {
      auto out = distance_T_.topRows(num_near);
      if (loops_) {
        times_velocity_map(distance_J_.topRows(num_near), out);
      } else {
        out = distance_J_.topRows(num_near);
      }
      for (int i = 0; i < num_near; ++i, ++mi) {
        Cu_.row(mi) = out.row(i).cwiseProduct(scale_.transpose());
        cu_[mi] = (S(o.min_distance) - distance_[static_cast<std::size_t>(near_[static_cast<std::size_t>(i)])]) / S(o.collision_horizon);
        row_key_[static_cast<std::size_t>(mi)] = 2 * num_limits + near_[static_cast<std::size_t>(i)];
      }
    }
    if (!options_.velocity_limits.empty())
      for (int i = 0; i < nc_; ++i) {
        if (!std::isfinite(limits_[i])) continue;
        const int key = 2 * num_limits + pairs_ + 2 * i;
        unit(i, scale_[i], -limits_[i], key);
        unit(i, -scale_[i], -limits_[i], key + 1);
      }
    general_rows_ = mi;
    for (int j = 0; j < units; ++j) {
      cu_[mi + j] = unit_bound_[static_cast<std::size_t>(j)];
      row_key_[static_cast<std::size_t>(mi + j)] = unit_key_[static_cast<std::size_t>(j)];
    }
    num_rows_ = mi + units;
    for (int r = 0; r < num_rows_; ++r) row_of_key_[static_cast<std::size_t>(row_key_[static_cast<std::size_t>(r)])] = r;
    return num_rows_;
  }
  /// Writes the unit rows into Cu_ (rows general_rows_ .. mi - 1), for the stages that take Cu_ whole.
  void fill_unit_rows(int mi) {
    for (int r = general_rows_; r < mi; ++r) {
      const std::size_t j = static_cast<std::size_t>(r - general_rows_);
      Cu_.row(r).setZero();
      Cu_(r, unit_column_[j]) = unit_coefficient_[j];
    }
  }
  /// The entries of T that are not zero, row by row: T is the identity off the loops and each
  /// sub-system's G on its coordinates (Lola: 42 of 46 x 30 entries), so J T as a dense product
  /// (Eigen's GEMM, its packing included) was a sixth of the step. Gathered at every step from T
  /// itself (a NaN entry counts: it reaches the product as it would have). Only the dependent
  /// rows are scanned: the row of independent coordinate c is the unit row e_c, whatever q (the
  /// backend's contract, y = v[independent_v_index] for v = T y), so its one entry is taken as it
  /// is. Scanning all 1,380 entries of Lola's T, one unpredictable branch each, was ~1 us of the
  /// step; its 16 dependent rows are 480 entries. Each entry is written at the next free slot and
  /// the count advances only when it is not zero: no branch to mispredict (the branch on each
  /// entry was 14 % of the step's own time).
  void gather_velocity_map_entries() {
    int count = 0;
    for (int r = 0; r < nv_; ++r) {
      const int own = independent_column_[static_cast<std::size_t>(r)];
      const int begin = own >= 0 ? own : 0, end = own >= 0 ? own + 1 : nc_;
      for (int c = begin; c < end; ++c) {
        const S value = T_(r, c);
        const std::size_t k = static_cast<std::size_t>(count);
        t_row_[k] = r;
        t_col_[k] = c;
        t_value_[k] = value;
        count += value != S(0) ? 1 : 0;
      }
    }
    t_count_ = count;
  }
  /// out = X T (X: rows x nv, out: rows x nc) from the gathered entries: column c of out is the
  /// sum of T(r, c) X.col(r) over T's entries in column c, added in row order.
  template <typename In, typename Out> void times_velocity_map(const In& X, Out& out) const {
    out.setZero();
    for (int k = 0; k < t_count_; ++k) {
      const std::size_t i = static_cast<std::size_t>(k);
      out.col(t_col_[i]) += t_value_[i] * X.col(t_row_[i]);
    }
  }
  /// x_c = T^T x (covector: gradient in solved coordinates), from T's gathered entries.
  void to_coordinates(const VecX<S>& x, VecX<S>& x_c) const {
    if (loops_) {
      x_c.setZero();
      for (int k = 0; k < t_count_; ++k) {
        const std::size_t i = static_cast<std::size_t>(k);
        x_c[t_col_[i]] += t_value_[i] * x[t_row_[i]];
      }
    } else {
      x_c = x;
    }
  }

 protected:
  Backend backend_;
  std::vector<Task> tasks_;

 private:
  DifferentialIkOptions options_;
  int nv_;
  bool loops_;
  int nc_, nf_, m_, pairs_ = 0;
  bool repulsion_ = false;  ///< a collision or joint-limit potential to descend
  bool qp_ = false;         ///< the QP form (QpStepOptions)
  int num_soft_ = 0, max_inequalities_ = 0, general_rows_ = 0;
  std::vector<int> unit_column_;  ///< per unit row (inequality_rows), its coordinate, coefficient and bound
  std::vector<S> unit_coefficient_, unit_bound_;
  /// The QP's warm start across steps (inequality_rows' keys): per row its key, per key its row
  /// (-1: not a row this step), the last solve's active rows' keys, the start rows handed over.
  std::vector<int> unit_key_, row_key_, row_of_key_, active_key_, start_row_;
  int num_rows_ = 0, num_active_keys_ = 0;
  DenseQp<S> solver_{1, 0, 1};
  MatX<S> Z_, Cu_, Ct_, soft_, soft_Z_, Gq_, Aw_, no_rows_;  ///< the QP form's: null basis, inequalities, soft rows, ...
  VecX<S> cu_, ct_, soft_target_, soft_residual_, aq_, xw_, no_values_, row_weight_;
  DampedLeastSquares<S> dls_;
  std::vector<TaskTarget<S>> targets_;
  S mass_ = S(1);
  Vec3<S> axis_scale_ = Vec3<S>::Ones();
  VecX<S> scale_, limits_;  ///< D = W^-1/2 (diagonal), velocity limits
  std::vector<S> X_WF_, frame_J_, distance_, normal_, witness_;
  std::vector<int> near_;
  Vec3<S> com_ = Vec3<S>::Zero();
  RowMatX Ag_, distance_J_, T_, distance_T_;
  std::vector<int> independent_column_;  ///< per v index, its independent coordinate (-1: a dependent one)
  std::vector<int> t_row_, t_col_;  ///< T's entries that are not zero (gather_velocity_map_entries)
  std::vector<S> t_value_;
  int t_count_ = 0;
  MatX<S> J_, A_;
  Eigen::Matrix<S, Eigen::Dynamic, 4, Eigen::RowMajor> to_null_;    ///< D0 P [u_c, (Bk D)^T] (null-space coordinates)
  Eigen::Matrix<S, Eigen::Dynamic, 2, Eigen::RowMajor> from_null_;  ///< [t_c, t_c + t_B s], then P^T times it
  VecX<S> xd_;
  Mat3X<S> Jcom_, Bk_;
  VecX<S> gradient_, gradient_c_, u1_, u2_, uc_, c_, secondary_, collision_;
  /// QpStepOptions::smoothing: the last step's command (weighted coordinates) and a work vector.
  VecX<S> u_last_, smooth_offset_;
};

/// The differential IK on the generic runtime: GenericBackend<S> over the model, with the tasks'
/// frames and the collision model's pairs. The model and the collision model are kept by
/// reference: they must outlive the controller. Tasks are resolved against the model too
/// (Task::frame), so a caller can read the model's frames for them.
template <typename S> class DifferentialIk : public BasicDifferentialIk<sim::GenericBackend<S>> {
  using Base = BasicDifferentialIk<sim::GenericBackend<S>>;

 public:
  DifferentialIk(const Model& model, const std::vector<TaskSpec>& tasks, const DifferentialIkOptions& options = {},
                 const collision::CollisionModel* collision_model = nullptr)
      : Base(make_backend(model, tasks, options, collision_model), tasks, options) {
    for (Task& t : this->tasks_)
      if (t.spec.kind != TaskKind::CenterOfMass) t.frame = *model.find_frame(t.spec.frame);
  }
  const Model& model() const { return this->backend_.model(); }

 private:
  static sim::GenericBackend<S> make_backend(const Model& model, const std::vector<TaskSpec>& tasks, const DifferentialIkOptions& options,
                                             const collision::CollisionModel* collision_model) {
    if (!model.closures.empty() && model.subsystems.empty())
      throw std::invalid_argument("DifferentialIk: model '" + model.name +
                                  "' has closures but no sub-systems: load it through the topology stage (gen::load_description)");
    if (tasks.empty()) throw std::invalid_argument("DifferentialIk: needs at least one primary task");
    std::vector<std::string> frames;
    for (const TaskSpec& spec : tasks) {
      (void)resolve_task(model, spec, 0);  // the model's own messages: an unknown frame, a bad gain
      if (spec.kind != TaskKind::CenterOfMass && std::find(frames.begin(), frames.end(), spec.frame) == frames.end())
        frames.push_back(spec.frame);
    }
    sim::GenericBackend<S> backend(model);
    backend.set_frames(frames);
    if (options.collision_avoidance) {
      if (!collision_model) throw std::invalid_argument("DifferentialIk: collision_avoidance needs a collision model (the scene's compounds and pairs)");
      check(options.collision);
      for (const collision::CollisionPair& p : collision_model->pairs)
        for (int c : {p.first, p.second})
          if (c < 0 || c >= static_cast<int>(collision_model->compounds.size()) ||
              collision_model->compounds[static_cast<std::size_t>(c)].shapes.empty() ||
              !(collision_model->compounds[static_cast<std::size_t>(c)].body.value() < model.num_bodies()))
            throw std::invalid_argument("DifferentialIk: collision pair refers to compound " + std::to_string(c) +
                                        ", which is missing, empty or on a body the model does not have");
      backend.set_collision_model(collision_model);
    }
    return backend;
  }
};

}  // namespace mbgen::control
