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
    repulsion_ = pairs_ > 0 || !options.joint_limits.limits.empty();
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
    uc_ = VecX<S>::Zero(nc_);
    c_ = VecX<S>::Zero(nc_);
    secondary_ = VecX<S>::Zero(nc_);
    collision_ = VecX<S>::Zero(nc_);
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
    if (!xd_.allFinite() || !dls_.compute(A_)) {
      v.setZero();
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
    if (options_.angular_momentum.enabled) {
      if (loops_) {
        times_velocity_map(Ag_.template bottomRows<3>(), Bk_);
      } else {
        Bk_ = Ag_.template bottomRows<3>();
      }
      Bk_.array().rowwise() *= scale_.transpose().array();
      Bk_.array().colwise() *= axis_scale_.array();  // per-axis weights: rows scaled by their square roots
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
    c_ = scale_.cwiseProduct(u1_ + u2_);
    if (!c_.allFinite()) {  // e.g. a distance that came out NaN: refuse rather than command it
      v.setZero();
      report.ok = false;
      return report;
    }
    S limit_scale = S(1);
    for (int i = 0; i < nc_; ++i)
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
  DampedLeastSquares<S> dls_;
  std::vector<TaskTarget<S>> targets_;
  S mass_ = S(1);
  Vec3<S> axis_scale_ = Vec3<S>::Ones();
  VecX<S> scale_, limits_;  ///< D = W^-1/2 (diagonal), velocity limits
  std::vector<S> X_WF_, frame_J_, distance_, normal_, witness_;
  std::vector<int> near_;
  Vec3<S> com_ = Vec3<S>::Zero();
  RowMatX Ag_, distance_J_, T_;
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
