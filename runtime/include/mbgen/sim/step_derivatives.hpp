#pragma once
// The derivatives of one simulator step (docs/derivatives.md, "One step"): for the step x+ = F(x,
// u) that a Simulator<Backend> takes from x = (q, v) with the joint forces u held over it, dx+/dx
// and dx+/du, what a DDP or a shooting method needs at each knot. The backend supplies each
// stage's dynamics and their derivatives (contact_dynamics_derivatives, sim/backend.hpp): the
// runtime's GenericBackend<S> by the generic algorithm, a generated NAME::Backend by the generated
// contact_forward_dynamics_derivatives (the contact_fd_derivatives output); the chain around them
// is this file's, the same for both.
//
// The step is the simulator's own: its integrator (explicit and symplectic Euler, RK4), its step
// length, its ground and contact law, its end stops (their stiffness as set_state fixed it), the
// quaternion renormalised at every stage and at the end. Each stage's derivative is the contact
// dynamics' (contact_dynamics_derivatives.hpp), the stops' diagonal added through M^-1.
//
// Tangent increments, as the dynamics' derivatives (rnea_derivatives.hpp): an input q (+) dq and an
// output q+ (+) dq+, dq and dq+ in v-space (integrate). The chain runs in the ambient coordinates
// the integrators add in (q: nq), columns (dq, dv, du) of 3 nv, and is mapped at both ends: in by
// dq_ambient = Q(q) dq (base: R dp, 1/2 quat * (dw, 0)), out by the normalisation's tangent,
// dp = R^T dp_ambient, dw = 2/|quat| vec(conj(quat^) * dquat_ambient).
//
// Not in the derivative (refused or left out, said here so a user knows): closed loops (the step's
// projection onto the closed set is not differentiated: refused), the adaptive and the linearly
// implicit integrators (refused), and a controller called within the step (u is the joint force
// held over the step). The simulator's passive forces (set_passive_forces) are a law of the state
// the derivative cannot see into: their Jacobians are the caller's to give (PassiveDerivatives),
// and a simulator with passive forces but without them is refused.
#include <functional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <unsupported/Eigen/AutoDiff>

#include "mbgen/algorithm/contact_dynamics_derivatives.hpp"
#include "mbgen/sim/simulator.hpp"

namespace mbgen::sim {

namespace detail {
template <typename B, typename = void> struct has_contact_dynamics_derivatives : std::false_type {};
template <typename B>
struct has_contact_dynamics_derivatives<
    B, std::void_t<decltype(std::declval<B&>().contact_dynamics_derivatives(
           std::declval<const typename B::Scalar*>(), std::declval<const typename B::Scalar*>(),
           std::declval<const typename B::Scalar*>(), std::declval<const typename B::Scalar*>(),
           std::declval<const typename B::Scalar*>(), std::declval<typename B::Scalar*>(), std::declval<typename B::Scalar*>(),
           std::declval<typename B::Scalar*>(), std::declval<typename B::Scalar*>(), std::declval<typename B::Scalar*>()))>>
    : std::true_type {};
}  // namespace detail

template <typename Backend> class StepDerivatives {
  static_assert(detail::has_contact_dynamics_derivatives<Backend>::value,
                "StepDerivatives needs the backend's contact_dynamics_derivatives: a generated robot has it when it is "
                "generated with the contact_fd_derivatives output (docs/derivatives.md)");

 public:
  using S = typename Backend::Scalar;
  /// The Jacobians of the simulator's passive forces p(q, v) at (q, v): dtau_dq and dtau_dv, nv x
  /// nv row-major each, dq a tangent increment (q (+) dq, as everywhere here), to be written whole.
  using PassiveDerivatives = std::function<void(const S* q, const S* v, S* dtau_dq, S* dtau_dv)>;

  /// The step `simulator` takes (call after its set_state: the stops' stiffness is fixed there),
  /// with `passive_derivatives` the Jacobians of its passive forces when it has any; a copy of its
  /// backend computes the stages (a runtime backend's copy refers to the same Model, which must
  /// outlive both, as it must outlive the simulator). Throws std::invalid_argument for closed loops, an integrator
  /// other than explicit_euler, symplectic_euler and rk4, and passive forces without their
  /// Jacobians (or Jacobians without passive forces). Allocates here; compute() does not.
  explicit StepDerivatives(Simulator<Backend>& simulator, PassiveDerivatives passive_derivatives = {})
      : backend_(simulator.backend()),
        options_(simulator.options()),
        nq_(backend_.nq()),
        nv_(backend_.nv()),
        floating_(backend_.floating_base()) {
    if (backend_.ny() != backend_.nv())
      throw std::invalid_argument("StepDerivatives: the model has closed loops; the step's projection onto the closed set is "
                                  "not differentiated (use the closed system's fd_derivatives, docs/derivatives.md)");
    const Integrator i = options_.integrator;
    if (i != Integrator::explicit_euler && i != Integrator::symplectic_euler && i != Integrator::rk4)
      throw std::invalid_argument(std::string("StepDerivatives: integrator ") + to_string(i) +
                                  " is not differentiated; pick explicit_euler, symplectic_euler or rk4");
    passive_ = simulator.passive_forces();
    passive_derivatives_ = std::move(passive_derivatives);
    if (passive_ && !passive_derivatives_)
      throw std::invalid_argument("StepDerivatives: the simulator has passive forces (set_passive_forces), a law the derivative "
                                  "cannot see into: give their Jacobians dtau/dq, dtau/dv as the constructor's second argument");
    if (!passive_ && passive_derivatives_)
      throw std::invalid_argument("StepDerivatives: passive-force Jacobians given, but the simulator has no passive forces "
                                  "(set_passive_forces before making the derivatives)");
    double g[kGroundInputs], l[kLawInputs];
    contact_inputs(options_.ground, options_.contact_parameters, g, l);
    // Without contact the simulator calls the contact-free dynamics: the same law at zero
    // stiffness and friction gives exactly zero forces and Jacobians (contact_law.hpp).
    if (!options_.contact) l[0] = 0, l[2] = 0;
    for (int k = 0; k < kGroundInputs; ++k) ground_[k] = S(g[k]);
    for (int k = 0; k < kLawInputs; ++k) law_[k] = S(l[k]);
    const auto& reports = simulator.joint_stops();
    stops_.reserve(simulator.backend().num_limited_joints());
    stops_.configure(simulator.backend(), options_.joint_stops);
    for (int k = 0; k < stops_.size(); ++k) stops_.set_inertia(k, reports[static_cast<std::size_t>(k)].inertia);
    const int rows = nq_ + nv_, cols = 3 * nv_;
    q0_ = VecX<S>::Zero(nq_), qs_ = q0_, qhat_ = q0_, v0_ = VecX<S>::Zero(nv_), vs_ = v0_, tau_ = v0_, tau_total_ = v0_;
    q_next_ = q0_, v_next_ = v0_;
    G0_ = MatX<S>::Zero(rows, cols), Gs_ = G0_, G_end_ = G0_;
    for (int s = 0; s < 4; ++s) kq_[s] = q0_, kv_[s] = v0_, dK_[s] = G0_;
    Aq_ = MatX<S>::Zero(nv_, nv_), Av_ = Aq_, stop_dq_ = Aq_, stop_dv_ = Aq_;
    if (passive_) passive_dq_ = RowMajor::Zero(nv_, nv_), passive_dv_ = passive_dq_;
    tangent_ = MatX<S>::Zero(nv_, cols);
    dx_dx_ = MatX<S>::Zero(2 * nv_, 2 * nv_), dx_du_ = MatX<S>::Zero(2 * nv_, nv_);
    dqdd_dq_ = RowMajor::Zero(nv_, nv_), dqdd_dv_ = dqdd_dq_, Minv_ = dqdd_dq_;
    contact_out_.assign(static_cast<std::size_t>(kContactOutputs * backend_.num_contacts()), S(0));
  }

  /// One step of options().step from (q: nq, v: nv) under the joint forces tau (nv) held: the
  /// state it ends in (q_next, v_next) and the Jacobians (dx_dx, dx_du). q's quaternion is taken
  /// normalised, as the simulator keeps it. No allocation.
  void compute(const S* q, const S* v, const S* tau) {
    const double h = options_.step;
    q0_ = Eigen::Map<const VecX<S>>(q, nq_);
    normalize_quaternion<S>(floating_, q0_.data());
    v0_ = Eigen::Map<const VecX<S>>(v, nv_);
    tau_ = Eigen::Map<const VecX<S>>(tau, nv_);
    G0_.setZero();
    input_map(q0_, G0_);
    G0_.block(nq_, nv_, nv_, nv_).setIdentity();
    switch (options_.integrator) {
      case Integrator::explicit_euler:
        stage(q0_, v0_, G0_, 0);
        q_next_ = q0_ + S(h) * kq_[0];
        v_next_ = v0_ + S(h) * kv_[0];
        G_end_ = G0_ + S(h) * dK_[0];
        break;
      case Integrator::symplectic_euler: {
        // v first, then q at the new v (Simulator::symplectic_euler).
        stage(q0_, v0_, G0_, 0);
        v_next_ = v0_ + S(h) * kv_[0];
        G_end_.bottomRows(nv_) = G0_.bottomRows(nv_) + S(h) * dK_[0].bottomRows(nv_);
        G_end_.topRows(nq_) = G0_.topRows(nq_);
        rate(q0_, v_next_, kq_[1]);
        add_rate_derivative(q0_, v_next_, G0_, G_end_, S(h), G_end_);
        q_next_ = q0_ + S(h) * kq_[1];
        break;
      }
      default: {  // rk4 (the constructor refused the rest)
        const ButcherTableau& t = ButcherTableau::rk4();
        stage(q0_, v0_, G0_, 0);
        for (int s = 1; s < t.stages; ++s) {
          qs_ = q0_, vs_ = v0_, Gs_ = G0_;
          for (int j = 0; j < s; ++j) {
            if (t.a[s][j] == 0) continue;
            const S w = S(h * t.a[s][j]);
            qs_ += w * kq_[j], vs_ += w * kv_[j], Gs_ += w * dK_[j];
          }
          stage(qs_, vs_, Gs_, s);
        }
        q_next_ = q0_, v_next_ = v0_, G_end_ = G0_;
        for (int s = 0; s < t.stages; ++s) {
          const S w = S(h * t.b[s]);
          q_next_ += w * kq_[s], v_next_ += w * kv_[s], G_end_ += w * dK_[s];
        }
      }
    }
    // Out: the normalisation's tangent at the sum, then the quaternion made unit.
    output_map(q_next_, G_end_.topRows(nq_), tangent_);
    dx_dx_.topRows(nv_) = tangent_.leftCols(2 * nv_);
    dx_du_.topRows(nv_) = tangent_.rightCols(nv_);
    dx_dx_.bottomRows(nv_) = G_end_.bottomRows(nv_).leftCols(2 * nv_);
    dx_du_.bottomRows(nv_) = G_end_.bottomRows(nv_).rightCols(nv_);
    normalize_quaternion<S>(floating_, q_next_.data());
  }

  const VecX<S>& q_next() const { return q_next_; }  ///< nq, the quaternion unit
  const VecX<S>& v_next() const { return v_next_; }  ///< nv
  /// 2nv x 2nv: rows (dq+, dv+), columns (dq, dv), dq and dq+ tangent increments.
  const MatX<S>& dx_dx() const { return dx_dx_; }
  /// 2nv x nv: rows (dq+, dv+), columns du.
  const MatX<S>& dx_du() const { return dx_du_; }
  /// The contact outputs of the last stage evaluated (kContactOutputs per sphere).
  const std::vector<S>& contact_outputs() const { return contact_out_; }

 private:
  using Block = Eigen::Block<MatX<S>>;

  /// Stage s at ambient (q, v) whose derivative by the inputs is G: kq_[s], kv_[s] and dK_[s].
  void stage(const VecX<S>& q, const VecX<S>& v, const MatX<S>& G, int s) {
    qhat_ = q;
    normalize_quaternion<S>(floating_, qhat_.data());
    tau_total_ = tau_;
    if (passive_) passive_(qhat_.data(), v.data(), tau_total_.data());  // as the simulator's stage adds them
    stops_.add_torques(qhat_.data(), v.data(), tau_total_.data(), false);
    stop_dq_.setZero(), stop_dv_.setZero();
    stops_.add_jacobians(qhat_.data(), v.data(), 0.0, stop_dv_, stop_dq_);
    backend_.contact_dynamics_derivatives(qhat_.data(), v.data(), tau_total_.data(), ground_, law_, kv_[s].data(),
                                          dqdd_dq_.data(), dqdd_dv_.data(), Minv_.data(), contact_out_.data());
    Aq_ = dqdd_dq_, Av_ = dqdd_dv_;
    // The stops' torques act on their own coordinate: a diagonal through M^-1.
    for (const JointStopReport<S>& r : stops_.reports()) {
      const int i = r.v_index;
      if (stop_dq_(i, i) != S(0)) Aq_.col(i) += Minv_.col(i) * stop_dq_(i, i);
      if (stop_dv_(i, i) != S(0)) Av_.col(i) += Minv_.col(i) * stop_dv_(i, i);
    }
    // The passive forces' Jacobians through M^-1 (dense: a law may couple joints).
    if (passive_) {
      passive_derivatives_(qhat_.data(), v.data(), passive_dq_.data(), passive_dv_.data());
      Aq_.noalias() += Minv_ * passive_dq_;
      Av_.noalias() += Minv_ * passive_dv_;
    }
    // dK_v = Aq T(q) G_q + Av G_v, plus M^-1 on the u columns.
    output_map(q, G.topRows(nq_), tangent_);
    dK_[s].bottomRows(nv_).noalias() = Aq_ * tangent_;
    dK_[s].bottomRows(nv_).noalias() += Av_ * G.bottomRows(nv_);
    dK_[s].bottomRightCorner(nv_, nv_) += Minv_;
    // dK_q: the configuration rate at (normalize(q), v).
    rate(q, v, kq_[s]);
    dK_[s].topRows(nq_).setZero();
    add_rate_derivative(q, v, G, G, S(1), dK_[s]);
  }

  /// The simulator's position rate at (normalize(q), v).
  void rate(const VecX<S>& q, const VecX<S>& v, VecX<S>& out) {
    qhat_ = q;
    normalize_quaternion<S>(floating_, qhat_.data());
    configuration_rate<S>(floating_, nq_, qhat_.data(), v.data(), out.data());
  }

  /// out.topRows(nq) += scale (d rate / dq Gq.topRows(nq) + d rate / dv Gv.bottomRows(nv)) at
  /// (normalize(q), v): the base's seven rows by forward-mode automatic differentiation over its
  /// thirteen inputs (the rotation, the quaternion product and the normalisation), v for the rest.
  void add_rate_derivative(const VecX<S>& q, const VecX<S>& v, const MatX<S>& Gq, const MatX<S>& Gv, S scale, MatX<S>& out) {
    const int b = floating_ ? 7 : 0, c = floating_ ? 6 : 0;
    out.block(b, 0, nq_ - b, out.cols()) += scale * Gv.block(nq_ + c, 0, nv_ - c, Gv.cols());
    if (!floating_) return;
    using AD = Eigen::AutoDiffScalar<Eigen::Matrix<S, 13, 1>>;
    AD qa[7], va[6], ra[7];
    for (int i = 0; i < 7; ++i) qa[i] = AD(q[i], 13, i);
    for (int i = 0; i < 6; ++i) va[i] = AD(v[i], 13, 7 + i);
    normalize_quaternion<AD>(true, qa);
    configuration_rate<AD>(true, 7, qa, va, ra);
    Eigen::Matrix<S, 7, 7> Jq;
    Eigen::Matrix<S, 7, 6> Jv;
    for (int i = 0; i < 7; ++i) {
      Jq.row(i) = ra[i].derivatives().template head<7>().transpose();
      Jv.row(i) = ra[i].derivatives().template tail<6>().transpose();
    }
    out.topRows(7).noalias() += scale * (Jq * Gq.topRows(7));
    out.topRows(7).noalias() += scale * (Jv * Gv.block(nq_, 0, 6, Gv.cols()));
  }

  /// G's q rows (nq x nv, columns dq) for the input q (+) dq at a unit q.
  void input_map(const VecX<S>& q, MatX<S>& G) const {
    const int b = floating_ ? 7 : 0, c = floating_ ? 6 : 0;
    G.block(b, c, nq_ - b, nv_ - c).setIdentity();
    if (!floating_) return;
    const S x = q[3], y = q[4], z = q[5], w = q[6];
    G.block(0, 0, 3, 3) = quaternion_to_rotation<S>(x, y, z, w);
    // 1/2 quat * (dw, 0): [w I + [q_v]x; -q_v^T] / 2.
    const Vec3<S> qv(x, y, z);
    G.block(3, 3, 3, 3) = S(0.5) * (w * Mat3<S>::Identity() + skew<S>(qv));
    G.block(6, 3, 1, 3) = S(-0.5) * qv.transpose();
  }

  /// out (nv x cols) = the tangent at normalize(q) of the ambient increments Gq (nq x cols).
  template <typename Rows> void output_map(const VecX<S>& q, const Rows& Gq, MatX<S>& out) const {
    const int b = floating_ ? 7 : 0, c = floating_ ? 6 : 0;
    out.bottomRows(nv_ - c) = Gq.bottomRows(nq_ - b);
    if (!floating_) return;
    const S norm = std::sqrt(q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6]);
    const S x = q[3] / norm, y = q[4] / norm, z = q[5] / norm, w = q[6] / norm;
    out.topRows(3).noalias() = quaternion_to_rotation<S>(x, y, z, w).transpose() * Gq.topRows(3);
    // 2/|q| vec(conj(q^) * dq) = 2/|q| (w dq_v - dq_w q_v - q_v x dq_v).
    const Vec3<S> qv(x, y, z);
    Eigen::Matrix<S, 3, 4> M;
    M.template leftCols<3>() = w * Mat3<S>::Identity() - skew<S>(qv);
    M.col(3) = -qv;
    out.middleRows(3, 3).noalias() = (S(2) / norm) * M * Gq.middleRows(3, 4);
  }

  Backend backend_;
  SimulatorOptions options_;
  JointStops<S> stops_;
  S ground_[kGroundInputs] = {}, law_[kLawInputs] = {};
  int nq_, nv_;
  bool floating_;
  VecX<S> q0_, qs_, qhat_, v0_, vs_, tau_, tau_total_, q_next_, v_next_;
  VecX<S> kq_[4], kv_[4];
  MatX<S> G0_, Gs_, G_end_, dK_[4], Aq_, Av_, stop_dq_, stop_dv_, tangent_, dx_dx_, dx_du_;
  using RowMajor = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  typename Simulator<Backend>::PassiveForces passive_;
  PassiveDerivatives passive_derivatives_;
  RowMajor passive_dq_, passive_dv_;
  RowMajor dqdd_dq_, dqdd_dv_, Minv_;  ///< the stage's, as the backend writes them
  std::vector<S> contact_out_;
};

}  // namespace mbgen::sim
