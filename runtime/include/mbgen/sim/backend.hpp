#pragma once
// The robot's functions, as the simulator (and the controller, and the study) consume them
// (DESIGN.md, "Backends"). A backend is any type with these members, S its Scalar; the
// generator emits one per robot (NAME::Backend, forwarding to the generated functions), and
// here are the runtime's, over a Model:
//
//   using Scalar = S;
//   int nq(), nv(), ny(); bool floating_base();   a floating base is q[0..7), v[0..6)
//   const int* independent_v_index();             ny v indices, ascending
//   int num_contacts(); double contact_radius(k); const char* contact_name(k)
//   double total_mass(); const double* gravity(); world, 3 entries
//   int num_limited_joints(); const char* limited_joint_name(k)
//   const int* limited_q_index(); const int* limited_v_index(); const double* limited_lower();
//   const double* limited_upper()                 the position ranges (joint_limits.hpp): the
//                                                 simulator's end stops (joint_stops.hpp)
//   void accelerations(q, v, tau, qdd)            every tree joint's (nv) at (q, v), forces tau (nv)
//   int closure_positions(q, subsystem = nullptr) closes the loops in place: 0 converged,
//                                                 1 not converged, 2 singular (dead point); the
//                                                 failing sub-system to *subsystem (-1 if none)
//   int close_loops(q, v, tol, subsystem = nullptr, relative_pivot_ratio = nullptr, worst_subsystem = nullptr)
//                                                 closure_positions to the residual tol (or the
//                                                 scalar's default, the larger), then (converged)
//                                                 v's dependent entries from its independent ones
//                                                 at the closed q, in one pass: the simulator's
//                                                 projection; the worst sub-system's pivot ratio
//                                                 relative to its assembled pose's (double*), and
//                                                 which sub-system that is (int*)
//   int num_closure_rows()                        nv - ny: the sub-systems' kept rows
//   void closure_constraints(q, v, Phi, J, gamma) those rows in full coordinates (J: rows x nv,
//                                                 row-major; J qdd = gamma): the simulator's soft
//                                                 span through a dead point
//   const char* subsystem_name(k)                 sub-system k's loop closures
//   void full_velocities(q, vy, v)                v = T vy
//   void velocity_map(q, T)                       nv x ny, row-major
//   void inverse_dynamics(q, v, qdd, tau)         the spanning tree's (no closure forces)
//   int na(); const int* actuated_v_index()       the actuated coordinates (v indices)
//   void actuator_forces(q, vy, ydd, tau_a, r)    the closed system's inverse dynamics for the
//                                                 actuators (algorithm/actuator_forces.hpp): na
//                                                 forces and the residual r (ny) on coordinates no
//                                                 actuator reaches (the floating base)
//   void mass_matrix(q, M)                        the tree's, nv x nv
//   void center_of_mass(q, com)
//   void contact_points(q, p, J)                  algorithm/contact_points.hpp: per sphere its
//                                                 centre (3) and a 6 x nv Jacobian block
//   void accelerations_with_contact(q, v, tau, ground, law, qdd, contacts)
//                                                 accelerations under tau and the ground's forces
//                                                 on the spheres (contact.hpp: contact_inputs,
//                                                 kContactOutputs per sphere); the simulator's step
//   double contact_exponent()                     the law's exponent it computes with; a backend
//                                                 with set_contact_exponent(e) takes any
//   void contact_dynamics_derivatives(q, v, tau, ground, law, qdd, dqdd_dq, dqdd_dv, Minv, contacts)
//                                                 accelerations_with_contact's qdd and its
//                                                 derivatives (nv x nv each, row-major; dq a
//                                                 tangent increment): a tree's, what
//                                                 StepDerivatives (step_derivatives.hpp) chains;
//                                                 optional (generated: the contact_fd_derivatives
//                                                 output)
//
// and what the differential IK (control/differential_ik.hpp) asks of it:
//   int num_frames(); const char* frame_name(k)   the frames it computes (generated: the scene's
//                                                 `jacobians:`; runtime: set_frames)
//   void task_kinematics(q, X_WF, J, com, Ag)     per frame its pose (12: [R | p] row-major) and
//                                                 its Jacobian (6 x nv row-major, world axes at
//                                                 the frame origin), the centre of mass, the
//                                                 centroidal momentum matrix (6 x nv row-major)
//   int num_distance_pairs()
//   void self_distances(q, d, normal, witness, J) the generated self_distances' layout (runtime:
//                                                 the pairs of set_collision_model)
//   void self_distances_near(q, threshold, d, near, num_near, normal, witness, J)
//                                                 the near set: only the pairs closer than
//                                                 threshold get rows (compact)
//
// All arrays are raw pointers (the generated API's form); no call allocates after construction.
// Backends differ only in how `accelerations` obtains qdd:
//   GenericBackend      the O(n) recursion with sub-systems (what the generator traces): it reads
//                       the independent velocities of v and returns T ydd + g;
//   KktBackend          the O(n^3) full-coordinate reference with Lagrange multipliers and
//                       Baumgarte gains: it reads all of v, so a drifting state is pulled back;
//   IndependentBackend  the O(n^3) reference in independent coordinates (G^T M G ydd = ...).
#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "mbgen/algorithm/actuator_forces.hpp"
#include "mbgen/algorithm/center_of_mass.hpp"
#include "mbgen/algorithm/centroidal.hpp"
#include "mbgen/algorithm/jacobian.hpp"
#include "mbgen/algorithm/constrained_dynamics.hpp"
#include "mbgen/algorithm/contact_dynamics.hpp"
#include "mbgen/algorithm/contact_dynamics_derivatives.hpp"
#include "mbgen/algorithm/contact_points.hpp"
#include "mbgen/algorithm/loop_forward_dynamics.hpp"
#include "mbgen/algorithm/subsystem_maps.hpp"
#include "mbgen/collision/compound_distance.hpp"
#include "mbgen/joint_limits.hpp"

namespace mbgen::sim {

namespace detail {

/// Whether a backend takes the contact law's exponent at run time (the runtime ones) or is built
/// for one (a generated one).
template <typename B, typename = void> struct has_set_contact_exponent : std::false_type {};
template <typename B>
struct has_set_contact_exponent<B, std::void_t<decltype(std::declval<B&>().set_contact_exponent(1.0))>> : std::true_type {};

template <typename S> using ConstMap = Eigen::Map<const VecX<S>>;
template <typename S> using RowMajorMap = Eigen::Map<Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;

/// What the three runtime backends share: the model, its work memory, the contact spheres and
/// every member of the concept except `accelerations`.
template <typename S> class ModelBackend {
 public:
  using Scalar = S;

  /// Throws std::invalid_argument for a model the simulator's state layout cannot hold: a
  /// floating joint anywhere but first, or a contact sphere on the world.
  ModelBackend(const Model& model, std::vector<ContactSphere> contacts, ClosureOptions closure)
      : model_(model), data_(model), contacts_(std::move(contacts)), closure_(closure), vy_(VecX<S>::Zero(0)) {
    for (int j = 1; j < model.num_joints(); ++j)
      if (model.joint(JointIndex(j)).type == JointType::Floating && model.joint(JointIndex(j)).idx_q != 0)
        throw std::invalid_argument("sim backend: joint '" + model.joint(JointIndex(j)).name +
                                    "' is floating but not the first joint; the simulator's state keeps a floating base at q[0..7)");
    for (const ContactSphere& c : contacts_)
      if (!c.body.valid() || c.body == kWorldBody || c.body.value() >= model.num_bodies())
        throw std::invalid_argument("sim backend: contact sphere '" + c.name + "' is not on a moving body of '" + model.name + "'");
    vy_ = VecX<S>::Zero(static_cast<int>(model_.structure().independent_v.size()));
    actuation_ = make_actuation(model, default_actuated_v(model));
    tau_contact_ = VecX<S>::Zero(model.nv());
    if (model.subsystems.empty()) derivatives_.emplace(model);
    for (const SubSystem& s : model.subsystems) {
      std::string name;
      for (int c : s.closures) name += (name.empty() ? "" : ", ") + model.closures[static_cast<std::size_t>(c)].name;
      subsystem_names_.push_back(name);
    }
    gravity_[0] = model.gravity.x(), gravity_[1] = model.gravity.y(), gravity_[2] = model.gravity.z();
    for (const JointLimit& l : joint_position_limits(model)) {
      limit_names_.push_back(l.joint);
      limit_q_.push_back(l.q_index), limit_v_.push_back(l.v_index);
      limit_lower_.push_back(l.lower), limit_upper_.push_back(l.upper);
    }
  }

  int nq() const { return model_.nq(); }
  int nv() const { return model_.nv(); }
  int ny() const { return static_cast<int>(model_.structure().independent_v.size()); }
  bool floating_base() const { return model_.floating_base(); }
  const int* independent_v_index() const { return model_.structure().independent_v.data(); }
  int na() const { return actuation_.num_actuators(); }
  const int* actuated_v_index() const { return actuation_.actuated_v.data(); }
  /// The actuated coordinates (v indices; default: the independent ones but a floating base, as
  /// the generator takes them when a description names none). Throws std::invalid_argument as
  /// make_actuation does. Allocates: call it at setup.
  void set_actuated(const std::vector<int>& actuated_v) { actuation_ = make_actuation(model_, actuated_v); }
  int num_contacts() const { return static_cast<int>(contacts_.size()); }
  double contact_radius(int k) const { return contacts_[static_cast<std::size_t>(k)].radius; }
  const char* contact_name(int k) const { return contacts_[static_cast<std::size_t>(k)].name.c_str(); }
  double total_mass() const { return model_.total_mass(); }
  const double* gravity() const { return gravity_; }
  int num_limited_joints() const { return static_cast<int>(limit_names_.size()); }
  const char* limited_joint_name(int k) const { return limit_names_[static_cast<std::size_t>(k)].c_str(); }
  const int* limited_q_index() const { return limit_q_.data(); }
  const int* limited_v_index() const { return limit_v_.data(); }
  const double* limited_lower() const { return limit_lower_.data(); }
  const double* limited_upper() const { return limit_upper_.data(); }
  const Model& model() const { return model_; }
  const std::vector<ContactSphere>& contacts() const { return contacts_; }
  ClosureOptions& closure_options() { return closure_; }

  int closure_positions(S* q, int* subsystem = nullptr) {
    Eigen::Map<VecX<S>> qm(q, nq());
    const ClosureResult<S> r = mbgen::closure_positions<S>(model_, data_, qm, closure_);
    if (subsystem) *subsystem = r.subsystem;
    return static_cast<int>(r.status);
  }
  int close_loops(S* q, S* v, double tolerance, int* subsystem = nullptr, double* relative_pivot_ratio = nullptr,
                  int* worst_subsystem = nullptr) {
    Eigen::Map<VecX<S>> qm(q, nq()), vm(v, nv());
    ClosureOptions options = closure_;
    options.tolerance = std::max(options.tolerance, tolerance);
    const ClosureResult<S> r = mbgen::close_loops<S>(model_, data_, qm, vm, options);
    if (subsystem) *subsystem = r.subsystem;
    if (relative_pivot_ratio) *relative_pivot_ratio = static_cast<double>(r.relative_pivot_ratio);
    if (worst_subsystem) *worst_subsystem = r.worst_subsystem;
    return static_cast<int>(r.status);
  }
  int num_closure_rows() const { return nv() - ny(); }
  /// The sub-systems' kept closure rows (SubSystem::rows, sub-system by sub-system) at (q, v), in
  /// full coordinates: residual Phi, Jacobian J (rows x nv, row-major) and bias gamma with
  /// J qdd = gamma (closure_constraints).
  void closure_constraints(const S* q, const S* v, S* Phi, S* J, S* gamma) {
    mbgen::closure_constraints<S>(model_, data_, ConstMap<S>(q, nq()), ConstMap<S>(v, nv()));
    int r = 0;
    for (const SubSystem& s : model_.subsystems)
      for (int row : s.rows) {
        Phi[r] = data_.Phi[row];
        gamma[r] = data_.gamma[row];
        RowMajorMap<S>(J + static_cast<std::ptrdiff_t>(r) * nv(), 1, nv()) = data_.Phi_q.row(row);
        ++r;
      }
  }
  /// Sub-system k's loop closures, comma-separated (as the generated Backend names them).
  const char* subsystem_name(int k) const { return subsystem_names_[static_cast<std::size_t>(k)].c_str(); }
  void full_velocities(const S* q, const S* vy, S* v) {
    Eigen::Map<VecX<S>> out(v, nv());
    mbgen::full_velocities<S>(model_, data_, ConstMap<S>(q, nq()), ConstMap<S>(vy, ny()), out);
  }
  void velocity_map(const S* q, S* T) { mbgen::velocity_map<S>(model_, data_, ConstMap<S>(q, nq()), RowMajorMap<S>(T, nv(), ny())); }
  // rnea and crba ignore the closures: they are the tree's, as the generated ones are.
  void inverse_dynamics(const S* q, const S* v, const S* qdd, S* tau) {
    Eigen::Map<VecX<S>>(tau, nv()) = rnea<S>(model_, data_, ConstMap<S>(q, nq()), ConstMap<S>(v, nv()), ConstMap<S>(qdd, nv()));
  }
  void actuator_forces(const S* q, const S* vy, const S* ydd, S* tau_a, S* residual) {
    mbgen::actuator_forces<S>(model_, data_, actuation_, ConstMap<S>(q, nq()), ConstMap<S>(vy, ny()), ConstMap<S>(ydd, ny()),
                              Eigen::Map<VecX<S>>(tau_a, na()), Eigen::Map<VecX<S>>(residual, ny()));
  }
  void mass_matrix(const S* q, S* M) { RowMajorMap<S>(M, nv(), nv()) = crba<S>(model_, data_, ConstMap<S>(q, nq())); }
  void center_of_mass(const S* q, S* com) {
    const Vec3<S>& c = mbgen::center_of_mass<S>(model_, data_, ConstMap<S>(q, nq()));
    for (int i = 0; i < 3; ++i) com[i] = c[i];
  }
  void contact_points(const S* q, S* p, S* J) { mbgen::contact_points<S>(model_, data_, contacts_, ConstMap<S>(q, nq()), p, J); }
  double contact_exponent() const { return contact_exponent_; }
  void set_contact_exponent(double e) { contact_exponent_ = e; }
  /// The tree's accelerations under tau and the ground's forces on the spheres, and their
  /// derivatives (contact_forward_dynamics_derivatives, contact_dynamics_derivatives.hpp): qdd
  /// (nv), dqdd/dq along q (+) dq, dqdd/dv, M^-1 (nv x nv each, row-major) and kContactOutputs
  /// numbers per sphere. Throws std::logic_error for a model with closed loops (whose step
  /// derivatives StepDerivatives refuses before any call).
  void contact_dynamics_derivatives(const S* q, const S* v, const S* tau, const S* ground, const S* law, S* qdd, S* dqdd_dq,
                                    S* dqdd_dv, S* Minv, S* contacts) {
    if (!derivatives_)
      throw std::logic_error("sim backend: contact_dynamics_derivatives of model '" + model_.name +
                             "', which has closed loops: the derivatives under the ground are a tree's");
    ContactDynamicsDerivatives<S>& d = *derivatives_;
    contact_forward_dynamics_derivatives<S>(model_, data_, d, contacts_, contact_exponent_, ConstMap<S>(q, nq()),
                                            ConstMap<S>(v, nv()), ConstMap<S>(tau, nv()), ground, law, contacts);
    Eigen::Map<VecX<S>>(qdd, nv()) = d.fd.ddq;
    RowMajorMap<S>(dqdd_dq, nv(), nv()) = d.fd.dddq_dq;
    RowMajorMap<S>(dqdd_dv, nv(), nv()) = d.fd.dddq_dv;
    RowMajorMap<S>(Minv, nv(), nv()) = d.fd.Minv;
  }

  /// The frames task_kinematics computes (none by default). Throws std::invalid_argument for a
  /// name the model does not have. Allocates: call it at setup.
  void set_frames(const std::vector<std::string>& names) {
    frames_.clear();
    frame_names_ = names;
    for (const std::string& name : names) {
      const auto f = model_.find_frame(name);
      if (!f) throw std::invalid_argument("backend: no frame named '" + name + "' in model '" + model_.name + "' (a URDF link or fixed joint name)");
      frames_.push_back(*f);
    }
    frame_J_ = Mat6X<S>::Zero(6, model_.nv());
  }
  int num_frames() const { return static_cast<int>(frames_.size()); }
  const char* frame_name(int k) const { return frame_names_[static_cast<std::size_t>(k)].c_str(); }
  /// Frame poses and Jacobians, centre of mass and centroidal momentum matrix from one pass of the
  /// kinematics (centroidal_momentum_matrix computes the joint Jacobians and frame placements).
  void task_kinematics(const S* q, S* X_WF, S* J, S* com, S* Ag) {
    const int nv = model_.nv();
    compute_joint_jacobians<S>(model_, data_, ConstMap<S>(q, nq()));  // poses, frames, data_.J: the frames' Jacobians
    const Mat6X<S>& A = mbgen::detail::centroidal_momentum_matrix_from_poses<S>(model_, data_);
    for (std::size_t k = 0; k < frames_.size(); ++k) {
      const SE3<S>& X = data_.X_WF[frames_[k]];
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) X_WF[12 * k + 4 * r + c] = X.rotation(r, c);
        X_WF[12 * k + 4 * r + 3] = X.translation[r];
      }
      frame_jacobian<S>(model_, data_, frames_[k], ReferenceFrame::LocalWorldAligned, frame_J_);
      RowMajorMap<S>(J + 6 * nv * k, 6, nv) = frame_J_;
    }
    for (int i = 0; i < 3; ++i) com[i] = data_.com[i];
    RowMajorMap<S>(Ag, 6, nv) = A;
  }
  /// The self-collision pairs self_distances computes (none by default; nullptr: none again). The
  /// collision model is kept by reference: it must outlive the backend. Allocates: call it at setup.
  void set_collision_model(const collision::CollisionModel* cm) {
    collision_model_ = cm;
    collision_data_.reset();
    if (cm) collision_data_.emplace(model_, *cm);
  }
  int num_distance_pairs() const { return collision_model_ ? static_cast<int>(collision_model_->pairs.size()) : 0; }
  /// Per pair: distance, unit normal from the first body to the second (3), witness points (6:
  /// first, second) and the distance's Jacobian row (nv), as the generated self_distances.
  void self_distances(const S* q, S* distance, S* normal, S* witness, S* J) {
    if (!collision_model_) return;
    compute_joint_jacobians<S>(model_, data_, ConstMap<S>(q, nq()));
    collision::compute_distances<S>(model_, data_, *collision_model_, *collision_data_);
    collision::compute_distance_jacobians<S>(model_, data_, *collision_model_, *collision_data_);
    for (std::size_t k = 0; k < collision_data_->distances.size(); ++k) {
      const auto& r = collision_data_->distances[k].result;
      distance[k] = r.distance;
      for (int i = 0; i < 3; ++i) {
        normal[3 * k + i] = r.normal[i];
        witness[6 * k + i] = r.point1[i];
        witness[6 * k + 3 + i] = r.point2[i];
      }
    }
    RowMajorMap<S>(J, num_distance_pairs(), model_.nv()) = collision_data_->jacobian;
  }
  /// The near set, as the generated self_distances_near: distance[k] for every pair (exact for a
  /// near pair, a lower bound >= threshold for a far one: collision::compute_near_distances); the
  /// near pairs' indices ascending in near[0 .. *num_near), and row i of normal (3), witness (6)
  /// and J (nv) for pair near[i].
  void self_distances_near(const S* q, S threshold, S* distance, int* near, int* num_near, S* normal, S* witness, S* J) {
    *num_near = 0;
    if (!collision_model_) return;
    collision::CollisionData<S>& cd = *collision_data_;
    compute_joint_jacobians<S>(model_, data_, ConstMap<S>(q, nq()));
    collision::compute_near_distances<S>(model_, data_, *collision_model_, threshold, cd);
    collision::compute_distance_jacobians<S>(model_, data_, *collision_model_, cd);
    for (std::size_t k = 0; k < cd.distances.size(); ++k) distance[k] = cd.distances[k].result.distance;
    for (int i = 0; i < cd.num_near; ++i) {
      const int k = cd.near[static_cast<std::size_t>(i)];
      const auto& r = cd.distances[static_cast<std::size_t>(k)].result;
      near[i] = k;
      for (int c = 0; c < 3; ++c) {
        normal[3 * i + c] = r.normal[c];
        witness[6 * i + c] = r.point1[c];
        witness[6 * i + 3 + c] = r.point2[c];
      }
      RowMajorMap<S>(J + static_cast<std::ptrdiff_t>(i) * model_.nv(), 1, model_.nv()) = cd.jacobian.row(k);
    }
    *num_near = cd.num_near;
  }

 protected:
  /// tau plus the ground's joint forces (contact_joint_forces, the generic twin of the generated
  /// contact_accelerations' first half), in a member buffer.
  const S* with_contact_forces(const S* q, const S* v, const S* tau, const S* ground, const S* law, S* contacts) {
    tau_contact_ = ConstMap<S>(tau, nv());
    contact_joint_forces<S>(model_, data_, contacts_, contact_exponent_, ConstMap<S>(q, nq()), v, ground, law, tau_contact_.data(),
                            contacts);
    return tau_contact_.data();
  }

  void gather_independent(const S* v) {
    for (int i = 0; i < ny(); ++i) vy_[i] = v[model_.structure().independent_v[static_cast<std::size_t>(i)]];
  }

  const Model& model_;
  Data<S> data_;
  std::vector<ContactSphere> contacts_;
  std::vector<std::string> subsystem_names_;
  std::vector<FrameIndex> frames_;
  std::vector<std::string> frame_names_;
  Mat6X<S> frame_J_ = Mat6X<S>::Zero(6, 0);
  const collision::CollisionModel* collision_model_ = nullptr;
  std::optional<collision::CollisionData<S>> collision_data_;
  ClosureOptions closure_;
  Actuation actuation_;
  VecX<S> vy_, tau_contact_;
  double gravity_[3] = {0, 0, 0};
  std::vector<std::string> limit_names_;  ///< joint_position_limits(model), by column
  std::vector<int> limit_q_, limit_v_;
  std::vector<double> limit_lower_, limit_upper_;
  double contact_exponent_ = ContactParameters{}.exponent;
  /// contact_dynamics_derivatives' work memory: a tree's only (none with loops).
  std::optional<ContactDynamicsDerivatives<S>> derivatives_;
};

}  // namespace detail

/// The O(n) articulated-body recursion with sub-systems as aggregate bodies: the generic twin of
/// the generated backend (same algorithm, interpreted).
template <typename S> class GenericBackend : public detail::ModelBackend<S> {
 public:
  explicit GenericBackend(const Model& model, std::vector<ContactSphere> contacts = {}, ClosureOptions closure = default_closure_options<S>())
      : detail::ModelBackend<S>(model, std::move(contacts), closure) {}

  void accelerations(const S* q, const S* v, const S* tau, S* qdd) {
    const int nq = this->nq(), nv = this->nv();
    if (this->model_.subsystems.empty()) {
      Eigen::Map<VecX<S>>(qdd, nv) = aba<S>(this->model_, this->data_, detail::ConstMap<S>(q, nq), detail::ConstMap<S>(v, nv),
                                           detail::ConstMap<S>(tau, nv));
      return;
    }
    this->gather_independent(v);
    forward_dynamics_loops_independent<S>(this->model_, this->data_, detail::ConstMap<S>(q, nq), this->vy_, detail::ConstMap<S>(tau, nv));
    Eigen::Map<VecX<S>>(qdd, nv) = this->data_.ddq;
  }
  /// The ground's forces as external body forces of the recursion (contact_dynamics.hpp), as the
  /// generated contact_accelerations: with loops, the contacts move with T vy too.
  void accelerations_with_contact(const S* q, const S* v, const S* tau, const S* ground, const S* law, S* qdd, S* contacts) {
    const int nq = this->nq(), nv = this->nv();
    Eigen::Map<VecX<S>>(qdd, nv) =
        contact_forward_dynamics<S>(this->model_, this->data_, this->contacts_, this->contact_exponent_, detail::ConstMap<S>(q, nq),
                                    detail::ConstMap<S>(v, nv), detail::ConstMap<S>(tau, nv), ground, law, contacts);
  }
};

/// The O(n^3) full-coordinate reference: [M Phi^T; Phi 0] with Lagrange multipliers and
/// Baumgarte stabilisation (constrained_dynamics.hpp). Uses every entry of v.
template <typename S> class KktBackend : public detail::ModelBackend<S> {
 public:
  explicit KktBackend(const Model& model, BaumgarteGains gains = {}, std::vector<ContactSphere> contacts = {},
                      ClosureOptions closure = default_closure_options<S>())
      : detail::ModelBackend<S>(model, std::move(contacts), closure), gains_(gains), ws_(model) {}

  void accelerations(const S* q, const S* v, const S* tau, S* qdd) {
    const int nq = this->nq(), nv = this->nv();
    Eigen::Map<VecX<S>>(qdd, nv) = forward_dynamics_kkt<S>(this->model_, this->data_, ws_, detail::ConstMap<S>(q, nq),
                                                           detail::ConstMap<S>(v, nv), detail::ConstMap<S>(tau, nv), gains_);
  }
  void accelerations_with_contact(const S* q, const S* v, const S* tau, const S* ground, const S* law, S* qdd, S* contacts) {
    accelerations(q, v, this->with_contact_forces(q, v, tau, ground, law, contacts), qdd);
  }
  BaumgarteGains& gains() { return gains_; }

 private:
  BaumgarteGains gains_;
  ConstrainedDynamicsWorkspace<S> ws_;
};

/// The O(n^3) reference in independent coordinates: G^T M G ydd = G^T (tau - C - g - M g_acc).
template <typename S> class IndependentBackend : public detail::ModelBackend<S> {
 public:
  explicit IndependentBackend(const Model& model, std::vector<ContactSphere> contacts = {}, ClosureOptions closure = default_closure_options<S>())
      : detail::ModelBackend<S>(model, std::move(contacts), closure), ws_(model) {}

  void accelerations(const S* q, const S* v, const S* tau, S* qdd) {
    const int nq = this->nq(), nv = this->nv();
    Eigen::Map<VecX<S>>(qdd, nv) = forward_dynamics_independent<S>(this->model_, this->data_, ws_, detail::ConstMap<S>(q, nq),
                                                                   detail::ConstMap<S>(v, nv), detail::ConstMap<S>(tau, nv));
  }
  void accelerations_with_contact(const S* q, const S* v, const S* tau, const S* ground, const S* law, S* qdd, S* contacts) {
    accelerations(q, v, this->with_contact_forces(q, v, tau, ground, law, contacts), qdd);
  }

 private:
  ConstrainedDynamicsWorkspace<S> ws_;
};

}  // namespace mbgen::sim
