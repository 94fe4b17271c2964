#pragma once
// The simulator's end stops (docs/simulation.md, "End stops"): each position range the backend
// lists (the description's <limit lower upper>, MJCF range) becomes a compliant unilateral stop at
// both ends, in the ground's Hunt-Crossley form (JointStopParameters, joint_limits.hpp, says why).
// A stop acts on its own coordinate of tau (nv); on a dependent joint of a loop that force reaches
// the independent coordinates through the velocity map (T^T tau), as every force does in the
// backends' accelerations, so a stop inside a linkage holds the linkage, loops closed.
#include <cmath>
#include <vector>

#include "mbgen/algorithm/contact_law.hpp"
#include "mbgen/joint_limits.hpp"

namespace mbgen::sim {

/// The law at one end: delta past the end (> 0 in the stop), delta_dot its rate. The push back into
/// the range, k delta^e + c delta_dot with Hunt and Crossley's c = k d delta^e, at most c_max
/// (JointStopParameters::max_damping_ratio says why; c_max <= 0: no cap), clamped at 0 (a stop
/// pushes, never pulls), and its derivatives by delta and delta_dot (0 where clamped), for the
/// linearly implicit integrator.
template <typename S> struct JointStopForce {
  S force = S(0), by_delta = S(0), by_rate = S(0);
};
template <typename S> JointStopForce<S> joint_stop_force(S delta, S delta_dot, double k, double d, double e, double c_max = 0) {
  JointStopForce<S> f;
  if (!(delta > S(0))) return f;
  const S spring = S(k) * contact_spring_power<S>(delta, e);
  const S spring_slope = S(k * e) * contact_spring_power<S>(delta, e - 1);
  S c = spring * S(d), c_slope = spring_slope * S(d);
  if (c_max > 0 && c > S(c_max)) c = S(c_max), c_slope = S(0);
  const S push = spring + c * delta_dot;
  if (!(push > S(0))) return f;
  f.force = push;
  f.by_delta = spring_slope + c_slope * delta_dot;
  f.by_rate = c;
  return f;
}

/// One stop as the simulator reports it.
template <typename S> struct JointStopReport {
  const char* joint = "";
  int q_index = 0, v_index = 0;
  double lower = 0, upper = 0;
  double stiffness = 0;  ///< k in use, N m/rad^e or N/m^e
  double damping = 0;    ///< d, s/rad or s/m
  double inertia = 0;    ///< m the stop feels at the start pose, kg m^2 or kg
  double max_damping = 0;  ///< c_max = 2 zeta sqrt(k m), N m s/rad or N s/m (0: no cap)
  S penetration = S(0);  ///< past the nearer end at the last evaluation (> 0 in the stop), rad or m
  S torque = S(0);       ///< on the joint's coordinate, N m or N (> 0 pushes q up)
  bool active = false;   ///< penetration > 0
  double time_active = 0;       ///< s of accepted steps that began in the stop, since set_state
  S max_penetration = S(0);     ///< over the states the accepted steps began from
};

/// The stops of one simulator: the ranges, the law, the reports. No allocation after configure().
template <typename S> class JointStops {
 public:
  /// Reserves room for `count` stops (the backend's ranges); configure() then never allocates.
  void reserve(int count) { stops_.reserve(static_cast<std::size_t>(count)); }

  /// The stops for the backend's ranges under `p`: none when p.enabled is false, none on a joint p
  /// sets free. Each then waits for set_inertia() (its default stiffness and its damping cap).
  template <typename Backend> void configure(const Backend& backend, const JointStopParameters& p) {
    stops_.clear();
    exponent_ = p.exponent;
    if (!p.enabled) return;
    for (int i = 0; i < backend.num_limited_joints(); ++i) {
      JointStopReport<S> r;
      r.joint = backend.limited_joint_name(i);
      const JointStopSetting* s = p.setting(r.joint);
      if (s && s->free) continue;
      r.q_index = backend.limited_q_index()[i], r.v_index = backend.limited_v_index()[i];
      r.lower = backend.limited_lower()[i], r.upper = backend.limited_upper()[i];
      r.stiffness = s && s->stiffness > 0 ? s->stiffness : 0;
      r.damping = s && s->damping >= 0 ? s->damping : p.damping;
      stops_.push_back(r);
    }
    frequency_ = p.frequency;
    max_damping_ratio_ = p.max_damping_ratio;
  }
  int size() const { return static_cast<int>(stops_.size()); }
  /// Stop k feels the inertia m (kg m^2 or kg): without a stiffness of its own it gets k = m (2 pi
  /// f)^2, and its damping is capped at 2 zeta sqrt(k m).
  void set_inertia(int k, double inertia) {
    JointStopReport<S>& r = stops_[static_cast<std::size_t>(k)];
    const double omega = 2 * M_PI * frequency_;
    r.inertia = inertia;
    if (r.stiffness <= 0) r.stiffness = inertia * omega * omega;
    r.max_damping = max_damping_ratio_ > 0 ? 2 * max_damping_ratio_ * std::sqrt(r.stiffness * inertia) : 0;
  }
  const std::vector<JointStopReport<S>>& reports() const { return stops_; }

  /// Adds the stops' torques at (q, v) to tau; `record` keeps them (and the penetrations) in the
  /// reports.
  void add_torques(const S* q, const S* v, S* tau, bool record) {
    for (JointStopReport<S>& r : stops_) {
      const S below = S(r.lower) - q[r.q_index], above = q[r.q_index] - S(r.upper);
      S torque = S(0);
      if (below > S(0)) torque = joint_stop_force<S>(below, -v[r.v_index], r.stiffness, r.damping, exponent_, r.max_damping).force;
      if (above > S(0)) torque = -joint_stop_force<S>(above, v[r.v_index], r.stiffness, r.damping, exponent_, r.max_damping).force;
      tau[r.v_index] += torque;
      if (!record) continue;
      r.penetration = below > above ? below : above;
      r.torque = torque;
      r.active = r.penetration > S(0);
    }
  }

  /// The stops' spring energy at q: k delta^(e+1) / (e+1) per stop entered (the conservative part
  /// of the law; the damping only dissipates).
  S energy(const S* q) const {
    using std::pow;
    S e = S(0);
    for (const JointStopReport<S>& r : stops_) {
      const S below = S(r.lower) - q[r.q_index], above = q[r.q_index] - S(r.upper);
      const S delta = below > above ? below : above;
      if (delta > S(0)) e += S(r.stiffness) * pow(delta, S(exponent_ + 1)) / S(exponent_ + 1);
    }
    return e;
  }

  /// The linearly implicit Euler's terms (Simulator::linearly_implicit_euler): A += d tau/dv + h
  /// d tau/dq and B += d tau/dq on each stop's diagonal entry, at (q, v).
  template <typename Matrix> void add_jacobians(const S* q, const S* v, double h, Matrix& A, Matrix& B) const {
    for (const JointStopReport<S>& r : stops_) {
      const S below = S(r.lower) - q[r.q_index], above = q[r.q_index] - S(r.upper);
      JointStopForce<S> f;
      if (below > S(0)) f = joint_stop_force<S>(below, -v[r.v_index], r.stiffness, r.damping, exponent_, r.max_damping);
      if (above > S(0)) f = joint_stop_force<S>(above, v[r.v_index], r.stiffness, r.damping, exponent_, r.max_damping);
      // tau = +-f(delta, delta_dot) with delta = +-(bound - q): d tau/dq = -f_delta, d tau/dv = -f_rate at either end.
      A(r.v_index, r.v_index) -= f.by_rate + S(h) * f.by_delta;
      B(r.v_index, r.v_index) -= f.by_delta;
    }
  }

  /// After an accepted step of length h that began at the recorded state: activity and depth.
  void accept(double h) {
    for (JointStopReport<S>& r : stops_) {
      if (r.active) r.time_active += h;
      if (r.penetration > r.max_penetration) r.max_penetration = r.penetration;
    }
  }
  /// The largest penetration recorded since set_state.
  S max_penetration() const {
    S m = S(0);
    for (const JointStopReport<S>& r : stops_) m = r.max_penetration > m ? r.max_penetration : m;
    return m;
  }

 private:
  std::vector<JointStopReport<S>> stops_;
  double exponent_ = 1, frequency_ = 100, max_damping_ratio_ = 1;
};

}  // namespace mbgen::sim
