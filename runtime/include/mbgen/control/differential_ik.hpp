#pragma once
// Differential inverse kinematics (resolved motion rate control) with a damped, weighted
// pseudo-inverse and secondary objectives in the null space of the primary tasks (DESIGN.md
// "Controller side"; thesis ch. 4, 5, 7).
//
// Coordinates. The controller solves for c = the velocity coordinates v (nv) of a tree, or the
// independent velocities y (ny, Data::independent_v order) of a model with closed loops, whose
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
//     (collision_potential.hpp; zero when no pair is within the activation distance) and Bk the
//     angular rows of the centroidal momentum matrix (times T). The minimiser in closed form:
//        C = N (Bk D)^T (n x 3),  s = (I / rho + C^T C)^-1 (r - C^T u_c),  r = k_des - Bk D u1,
//        u2 = N u_c + C s,
//     a 3 x 3 solve whatever the robot. Every term of u2 lies in range(N), so A u2 = 0 to
//     round-off: the secondary objectives never disturb the primary tasks. The first term keeps
//     the collision motion as it is when the momentum objective is off; rho weighs momentum
//     tracking against it (1/rho acts as the damping of the momentum objective).
//  3. c = D (u1 + u2); with velocity limits, c is scaled uniformly by the largest factor <= 1
//     that respects them (direction kept: primary and secondary are slowed together, the
//     null-space property holds). v = T c.
//
// Allocation: the constructor sizes everything from the model and the task list; step() does
// not allocate and does not throw (tests/test_differential_ik.cpp checks it under a malloc guard).
// Errors in the configuration throw std::invalid_argument at construction, naming what is wrong.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Cholesky>

#include "mbgen/algorithm/centroidal.hpp"
#include "mbgen/algorithm/subsystem_maps.hpp"
#include "mbgen/control/collision_potential.hpp"
#include "mbgen/control/damped_least_squares.hpp"
#include "mbgen/control/task.hpp"
#include "mbgen/data.hpp"

namespace mbgen::control {

struct AngularMomentumOptions {
  bool enabled = false;
  double weight = 1e4;  ///< rho: weight of |k - k_des|^2 against |u2 - u_c|^2 (kg m^2/s)^-2
};

struct DifferentialIkOptions {
  DampingOptions damping{0.0, 1e-2, 1e-2, 1e-10};  ///< primary stack (singular region 0.01, max damping 0.01)
  std::vector<double> weights;          ///< per solved coordinate, > 0; empty: all 1
  std::vector<double> velocity_limits;  ///< per solved coordinate, > 0 (inf allowed); empty: none
  /// Self-collision avoidance: needs the collision model given to the constructor.
  bool collision_avoidance = false;
  CollisionPotentialOptions collision;
  AngularMomentumOptions angular_momentum;
};

/// What a step did (no exceptions in the step: a failure is reported here, qd is then zero).
struct StepReport {
  bool ok = false;          ///< false if the primary Jacobian, a target or the result was not finite
  int rank = 0;             ///< numerical rank of the weighted primary Jacobian
  double smallest_singular_value = 0;
  int active_pairs = 0;     ///< collision pairs within the activation distance
  double limit_scale = 1;   ///< factor applied to respect the velocity limits (1: none active)
};

template <typename S> class DifferentialIk {
 public:
  /// tasks: the primary stack (at least one). collision_model: the scene's compounds and kept
  /// pairs (needed iff options.collision_avoidance). The model and the collision model are kept
  /// by reference: they must outlive the controller.
  DifferentialIk(const Model& model, const std::vector<TaskSpec>& tasks, const DifferentialIkOptions& options = {},
                 const collision::CollisionModel* collision_model = nullptr)
      : model_(model), options_(options), collision_model_(collision_model), data_(model),
        loops_(!model.subsystems.empty()), nc_(static_cast<int>(data_.independent_v.size())),
        m_(count_rows(tasks)), dls_(m_, nc_, options.damping) {
    if (!model.closures.empty() && model.subsystems.empty())
      throw std::invalid_argument("DifferentialIk: model '" + model.name +
                                  "' has closures but no sub-systems: load it through the topology stage (gen::load_description)");
    int row = 0;
    for (const TaskSpec& spec : tasks) {
      for (const Task& t : tasks_)
        if (t.spec.name == spec.name) throw std::invalid_argument("DifferentialIk: two tasks named '" + spec.name + "'");
      tasks_.push_back(resolve_task(model, spec, row));
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
      collision_data_.emplace(model, *collision_model);
    }
    if (options.angular_momentum.enabled && (!(options.angular_momentum.weight > 0) || !std::isfinite(options.angular_momentum.weight)))
      throw std::invalid_argument("DifferentialIk: angular_momentum.weight must be finite and > 0, got " +
                                  std::to_string(options.angular_momentum.weight));
    J_ = MatX<S>::Zero(m_, model.nv());
    xd_ = VecX<S>::Zero(m_);
    A_ = MatX<S>::Zero(m_, nc_);
    T_ = MatX<S>::Zero(model.nv(), loops_ ? nc_ : 0);
    Jcom_ = Mat3X<S>::Zero(3, model.nv());
    frame_J_ = Mat6X<S>::Zero(6, model.nv());
    gradient_ = VecX<S>::Zero(model.nv());
    gradient_c_ = VecX<S>::Zero(nc_);
    Bk_ = Mat3X<S>::Zero(3, nc_);
    C_ = Eigen::Matrix<S, Eigen::Dynamic, 3>::Zero(nc_, 3);
    column_ = VecX<S>::Zero(nc_);
    u1_ = VecX<S>::Zero(nc_);
    u2_ = VecX<S>::Zero(nc_);
    uc_ = VecX<S>::Zero(nc_);
    c_ = VecX<S>::Zero(nc_);
    secondary_ = VecX<S>::Zero(nc_);
    collision_ = VecX<S>::Zero(nc_);
  }

  const Model& model() const { return model_; }
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
    centroidal_momentum_matrix<S>(model_, data_, q);  // joint Jacobians, frame poses, CoM, A_G
    Jcom_ = data_.Ag.template topRows<3>() / data_.mass;
    for (std::size_t i = 0; i < tasks_.size(); ++i)
      task_rows_and_velocity<S>(model_, data_, tasks_[i], targets_[i], Jcom_, J_, xd_, frame_J_);
    if (loops_) {
      mbgen::velocity_map<S>(model_, data_, q, T_);
      A_.noalias() = J_ * T_;
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

    // Collision: u_c = -D T^T dP/dq, projected into the null space.
    uc_.setZero();
    if (collision_data_) {
      collision::compute_distances<S>(model_, data_, *collision_model_, *collision_data_);
      collision::compute_distance_jacobians<S>(model_, data_, *collision_model_, *collision_data_);
      report.active_pairs = collision_potential_gradient<S>(*collision_data_, options_.collision, gradient_);
      to_coordinates(gradient_, gradient_c_);
      uc_ = -scale_.cwiseProduct(gradient_c_);
      dls_.project_to_null(uc_);
    }
    u2_ = uc_;
    if (options_.angular_momentum.enabled) {
      if (loops_) {
        Bk_.noalias() = data_.Ag.template bottomRows<3>() * T_;
      } else {
        Bk_ = data_.Ag.template bottomRows<3>();
      }
      Bk_.array().rowwise() *= scale_.transpose().array();
      for (int k = 0; k < 3; ++k) {
        column_ = Bk_.row(k).transpose();
        dls_.project_to_null(column_);
        C_.col(k) = column_;
      }
      const Vec3<S> r = angular_momentum_target - Bk_ * u1_;
      Mat3<S> M;
      M.noalias() = C_.transpose() * C_;
      M.diagonal().array() += S(1) / S(options_.angular_momentum.weight);
      const Vec3<S> s = Eigen::LLT<Mat3<S>>(M).solve(r - C_.transpose() * uc_);
      u2_.noalias() += C_ * s;
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
      v.noalias() = T_ * c_;
    } else {
      v = c_;
    }
    return report;
  }

  // Results of the last step (for logging and tests).
  const MatX<S>& primary_jacobian() const { return J_; }          ///< m x nv, world axes
  const VecX<S>& primary_velocity() const { return xd_; }         ///< m: desired task velocity incl. feedback
  const MatX<S>& velocity_map() const { return T_; }              ///< nv x ny (loops only; empty for a tree)
  const VecX<S>& coordinates_velocity() const { return c_; }      ///< nc: the solved velocity (after limits)
  /// nc: the secondary part D u2 of the solved velocity (before limits): in null(J T).
  const VecX<S>& secondary_velocity() const { return secondary_; }
  const VecX<S>& collision_velocity() const { return collision_; }  ///< nc: D N u_c (before limits)
  const VecX<S>& collision_gradient() const { return gradient_; }          ///< nv: dP/dq
  const collision::CollisionData<S>* collision_data() const { return collision_data_ ? &*collision_data_ : nullptr; }
  Data<S>& data() { return data_; }

 private:
  static int count_rows(const std::vector<TaskSpec>& tasks) {
    if (tasks.empty()) throw std::invalid_argument("DifferentialIk: needs at least one primary task");
    int m = 0;
    for (const TaskSpec& t : tasks) m += task_rows(t.kind);
    return m;
  }
  std::string size_message(const char* what, std::size_t got) const {
    return std::string("DifferentialIk: ") + what + " has " + std::to_string(got) + " entries, expected " + std::to_string(nc_) +
           (loops_ ? " (one per independent velocity: the model has closed loops)" : " (one per velocity coordinate, nv)");
  }
  /// x_c = T^T x (covector: gradient in solved coordinates).
  void to_coordinates(const VecX<S>& x, VecX<S>& x_c) const {
    if (loops_) {
      x_c.noalias() = T_.transpose() * x;
    } else {
      x_c = x;
    }
  }

  const Model& model_;
  DifferentialIkOptions options_;
  const collision::CollisionModel* collision_model_;
  Data<S> data_;
  bool loops_;
  int nc_, m_;
  DampedLeastSquares<S> dls_;
  std::vector<Task> tasks_;
  std::vector<TaskTarget<S>> targets_;
  std::optional<collision::CollisionData<S>> collision_data_;
  VecX<S> scale_, limits_;  ///< D = W^-1/2 (diagonal), velocity limits
  MatX<S> J_, A_, T_;
  Eigen::Matrix<S, Eigen::Dynamic, 3> C_;  ///< N (Bk D)^T
  VecX<S> xd_;
  Mat3X<S> Jcom_, Bk_;
  Mat6X<S> frame_J_;
  VecX<S> gradient_, gradient_c_, column_, u1_, u2_, uc_, c_, secondary_, collision_;
};

}  // namespace mbgen::control
