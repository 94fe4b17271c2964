#pragma once
// A simple walking pattern for a biped's controller (docs/control.md, "Walking"; used by
// mbgen_walk, and from Python as mbgen.WalkingPattern): footsteps, the ZMP reference they imply,
// a centre-of-mass trajectory consistent with the linear inverted pendulum (LIPM), and swing-foot
// trajectories.
//
// The CoM. The LIPM at height z_c is  c'' = w^2 (c - p),  w = sqrt(g / z_c), p the ZMP. For a
// ZMP reference p(t) known over the whole walk, its one bounded solution is the two-sided
// exponential smoothing of p:
//   c(t) = (w / 2) integral exp(-w |t - s|) p(s) ds
// (it satisfies the equation, and any other solution adds exp(+w t) or exp(-w (t - T)) terms that
// diverge at one end). On a grid of step dt this is a forward and a backward first-order
// recursion, each the exact convolution of the piecewise-linear p with exp(-w t): O(n), no preview
// gain to tune. p stays at the stance foot's centre in single support and moves linearly to the
// next foot in double support; the walk starts and ends standing with p between the feet (it
// moves there from the last stance foot over one double support).
//
// The swing foot. From its last footstep to its next during single support: horizontal position
// and yaw by a quintic (zero velocity and acceleration at both ends), height by the bump
// 64 u^3 (1 - u)^3 of `step_height`: the foot leaves and lands with zero velocity and
// acceleration (a jump in the swing leg's acceleration is a spike in the ground's yaw torque).
// With `swing_bulge` the path also bends outward, across the foot's heading, by that much at
// mid-swing (the lift's profile): a narrow step's straight path brushes the stance ankle.
//
// The heading. The feet turn in pulses, one per swing; a body that followed their mean yaw would
// turn in pulses too, and its yaw momentum, started and stopped at every step, would need the
// ground's torque each time. The pattern's heading is that mean smoothed over a step (three
// centred running means one step wide), with its rate: what the torso follows.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "mbgen/spatial/types.hpp"

namespace mbgen::walking {

/// Where a foot stands: its frame's origin (world) and yaw about the vertical.
struct Footstep {
  Vec3<double> position = Vec3<double>::Zero();
  double yaw = 0.0;
  int foot = 0;  ///< 0 left, 1 right
};

struct PatternOptions {
  int steps = 6;                 ///< steps taken (alternating, the first with `first_foot`)
  double step_length = 0.25;     ///< m, forward per step (a stride is two steps)
  double step_time = 0.4;        ///< s per step: double support then single support
  double double_support = 0.08;  ///< s of each step in double support
  double step_height = 0.05;     ///< m, swing foot clearance
  double swing_bulge = 0.0;      ///< m the swing foot's path bends outward at mid-swing
  double width_scale = 1.0;      ///< the feet's lateral distance, relative to the standing pose's
  double turn_per_step = 0.0;    ///< rad of yaw per step (a turn to the left when positive)
  double com_height = 0.0;       ///< m above the feet for the LIPM; 0: the standing pose's
  double start_time = 0.5;       ///< s standing before the first step (the CoM moves over the feet in its first 80 %)
  double end_time = 0.8;         ///< s standing after the last
  int first_foot = 1;            ///< the first swing foot (1: the right, the ZMP going left first)
};

/// Reference of every task at one instant.
struct PatternSample {
  double t = 0;
  Vec3<double> com, com_velocity, zmp;
  Vec3<double> foot[2], foot_velocity[2];
  double foot_yaw[2] = {0, 0}, foot_yaw_rate[2] = {0, 0};
  double heading = 0, heading_rate = 0;  ///< the feet's mean yaw smoothed over a step (above), rad and rad/s
  int stance = -1;  ///< the stance foot in single support, -1 in double support
};

namespace detail {
/// Quintic blend s(u) with s, s', s'' = 0, 0, 0 at u = 0 and 1, 0, 0 at u = 1; and ds/du.
inline double quintic(double u) { return u * u * u * (10 + u * (-15 + 6 * u)); }
inline double quintic_rate(double u) { return 30 * u * u * (1 - u) * (1 - u); }
}  // namespace detail

class WalkingPattern {
 public:
  const PatternOptions& options() const { return options_; }
  /// left, right: the feet's frames at the standing pose (world), com: the CoM there.
  WalkingPattern(const Vec3<double>& left, const Vec3<double>& right, const Vec3<double>& com, const PatternOptions& o, double dt)
      : options_(o), dt_(dt) {
    if (!(dt > 0) || !(o.step_time > o.double_support) || !(o.double_support >= 0) || o.steps < 1)
      throw std::invalid_argument("WalkingPattern: needs dt > 0, step_time > double_support >= 0 and at least one step");
    const double z_c = o.com_height > 0 ? o.com_height : com.z() - 0.5 * (left.z() + right.z());
    omega_ = std::sqrt(9.81 / z_c);
    // Footsteps: the standing feet, then each step moves the swing foot one step_length forward
    // (along the current heading) and to its side of the path at the scaled half-width.
    const Vec3<double> mid = 0.5 * (left + right);
    const double half_width = 0.5 * (left - right).norm() * o.width_scale;
    steps_.push_back({left, 0.0, 0});
    steps_.push_back({right, 0.0, 1});
    Vec3<double> path = mid;
    double heading = 0.0;
    int swing = o.first_foot;
    for (int k = 0; k < o.steps; ++k) {
      heading += o.turn_per_step;
      const bool last = k == o.steps - 1;
      path += Vec3<double>(std::cos(heading), std::sin(heading), 0) * (last ? 0.5 : 1.0) * o.step_length;
      const Vec3<double> side(-std::sin(heading), std::cos(heading), 0);
      Footstep f{path + (swing == 0 ? 1.0 : -1.0) * half_width * side, heading, swing};
      f.position.z() = (swing == 0 ? left : right).z();
      steps_.push_back(f);
      swing = 1 - swing;
    }
    // The last step closes the feet (half a step): one more with the other foot beside it.
    const Vec3<double> side(-std::sin(heading), std::cos(heading), 0);
    Footstep f{path + (swing == 0 ? 1.0 : -1.0) * half_width * side, heading, swing};
    f.position.z() = (swing == 0 ? left : right).z();
    steps_.push_back(f);
    duration_ = o.start_time + (o.steps + 1) * o.step_time + o.end_time;
    build(com);
  }

  double duration() const { return duration_; }
  double dt() const { return dt_; }
  int samples() const { return static_cast<int>(samples_.size()); }
  const PatternSample& sample(int k) const { return samples_[static_cast<std::size_t>(k)]; }
  const std::vector<Footstep>& footsteps() const { return steps_; }
  double omega() const { return omega_; }

  /// The vertical angular momentum about the CoM (per sample, kg m^2/s) for which the ground's
  /// yaw torque about the ZMP vanishes, for a body of `mass` whose CoM moves as the pattern's and
  /// whose centre of pressure is the pattern's ZMP. About the centre of pressure p the ground's
  /// moment is vertical, tau_z, and about the CoM the angular momentum changes by it plus the
  /// moment of the ground force f = m (c'' - g):
  ///   k_z' = tau_z + ((p - c) x f)_z = tau_z + m ((p - c)_x c''_y - (p - c)_y c''_x),
  /// so tau_z = 0 needs k_z(t) = m int ((p - c)_x c''_y - (p - c)_y c''_x) dt, from 0 at rest.
  /// Zero for the uncorrected pattern whose force points along c - p (the pendulum's law, which
  /// makes the bracket vanish); not zero once the CoM is corrected for the whole body
  /// (correct_com), whose force does not. Trapezoidal rule over the samples, c'' by central
  /// differences. The walk need not end with the integral at zero (Lola's straight walk: 0.05
  /// of its 0.9 kg m^2/s peak), and a robot standing still has none: what is left is taken out
  /// linearly over the steps, a constant yaw torque of (what is left) / (their duration), below
  /// 0.02 N m there.
  std::vector<double> yaw_free_momentum(double mass) const {
    if (!(mass > 0) || !std::isfinite(mass))
      throw std::invalid_argument("WalkingPattern::yaw_free_momentum: the mass must be positive and finite, got " + std::to_string(mass));
    const std::size_t n = samples_.size();
    std::vector<double> rate(n, 0.0), k(n, 0.0);
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const Vec3<double> cdd = (samples_[i + 1].com - 2 * samples_[i].com + samples_[i - 1].com) / (dt_ * dt_);
      const Vec3<double> r = samples_[i].zmp - samples_[i].com;
      rate[i] = mass * (r.x() * cdd.y() - r.y() * cdd.x());
    }
    for (std::size_t i = 1; i < n; ++i) k[i] = k[i - 1] + 0.5 * dt_ * (rate[i - 1] + rate[i]);
    const double left = k[n - 1], begin = options_.start_time, end = duration_ - options_.end_time;
    for (std::size_t i = 0; i < n; ++i) k[i] -= left * std::clamp((samples_[i].t - begin) / (end - begin), 0.0, 1.0);
    return k;
  }

  /// 0 at the start, rising (the quintic blend) to 1 at the end of the start's settling time
  /// (0.8 start_time), 1 after: how much of the CoM correction applies at time t (1 throughout
  /// without a standing start).
  double settled(double t) const { return options_.start_time > 0 ? 1 - start_blend(t).value : 1.0; }

  /// Moves the CoM so that the whole body, not only the pendulum, keeps the ZMP on its
  /// reference: `zmp_error[k]` is the full-body ZMP minus the reference at sample k (x, y) of a
  /// motion that tracked this pattern. The pendulum's ZMP responds to a CoM change dc as
  /// dp = dc - dc'' / w^2, so dc = the bounded solution for -error (bounded_lipm) cancels the
  /// error to first order; the reference ZMP is unchanged. Applied again on the corrected
  /// motion's error it converges (Kajita et al. 2003, the second stage of their preview control;
  /// Takenaka's iterations): each pass removes what the pendulum model missed in the last.
  void correct_com(const std::vector<Eigen::Vector2d>& zmp_error) {
    const std::size_t n = samples_.size();
    if (zmp_error.size() != n) throw std::invalid_argument("WalkingPattern::correct_com: one ZMP error per sample");
    // The robot starts at rest where the pattern's CoM starts: the correction fades in over the
    // settling time of the start (start_blend), and so does the error it answers, so that an
    // error it may not cancel there does not pile up pass after pass.
    std::vector<double> fade(n), ex(n), ey(n);
    for (std::size_t k = 0; k < n; ++k) {
      fade[k] = settled(samples_[k].t);
      ex[k] = -fade[k] * zmp_error[k].x(), ey[k] = -fade[k] * zmp_error[k].y();
    }
    std::vector<double> dx = bounded_lipm(ex), dy = bounded_lipm(ey);
    for (std::size_t k = 0; k < n; ++k) dx[k] *= fade[k], dy[k] *= fade[k];
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t a = k > 0 ? k - 1 : 0, b = std::min(n - 1, k + 1);
      samples_[k].com += Vec3<double>(dx[k], dy[k], 0);
      samples_[k].com_velocity += Vec3<double>(dx[b] - dx[a], dy[b] - dy[a], 0) / (static_cast<double>(b - a) * dt_);
    }
  }

 private:
  /// Every sample: each foot at its current footstep or swinging to its next, the ZMP, then the CoM.
  void build(const Vec3<double>& com0) {
    const PatternOptions& o = options_;
    const int n = static_cast<int>(std::floor(duration_ / dt_)) + 1;
    samples_.resize(static_cast<std::size_t>(n));
    // Feet: the index of each foot's current footstep advances at each of its steps.
    std::vector<double> zmp_x(static_cast<std::size_t>(n)), zmp_y(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) {
      PatternSample& s = samples_[static_cast<std::size_t>(k)];
      s.t = k * dt_;
      int current[2] = {0, 1};  // footstep index per foot
      int step = -1;            // the step in progress
      double phase = 0;         // time into it
      const double walking = s.t - o.start_time;
      const int steps_total = static_cast<int>(steps_.size()) - 2;
      if (walking >= 0) {
        // One floor, not a comparison per step: at a step's boundary both tests could fail in
        // floating point and leave a sample with no step.
        const int j = static_cast<int>(std::floor(walking / o.step_time));
        for (int i = 0; i < std::min(j, steps_total); ++i) current[steps_[static_cast<std::size_t>(i + 2)].foot] = i + 2;
        if (j < steps_total) {
          step = j;
          phase = std::max(0.0, walking - j * o.step_time);
        }
      }
      s.stance = -1;
      for (int foot = 0; foot < 2; ++foot) {
        const Footstep& at = steps_[static_cast<std::size_t>(current[foot])];
        s.foot[foot] = at.position;
        s.foot_velocity[foot].setZero();
        s.foot_yaw[foot] = at.yaw;
        s.foot_yaw_rate[foot] = 0;
      }
      Vec3<double> zmp = 0.5 * (s.foot[0] + s.foot[1]);
      if (step >= 0) {
        const Footstep& next = steps_[static_cast<std::size_t>(step + 2)];
        const int swing = next.foot, stance = 1 - swing;
        const Vec3<double>& from = steps_[static_cast<std::size_t>(current[swing])].position;
        const Vec3<double> stance_at = s.foot[stance];
        if (phase < o.double_support) {
          // ZMP from where it was (between the feet for the first step, else the last stance
          // foot, which is the current swing foot) to the new stance foot.
          const Vec3<double> start = step == 0 ? Vec3<double>(0.5 * (s.foot[0] + s.foot[1])) : from;
          zmp = start + (stance_at - start) * (phase / o.double_support);
        } else {
          s.stance = stance;
          zmp = stance_at;
          const double T = o.step_time - o.double_support, u = (phase - o.double_support) / T;
          const double b = detail::quintic(u), db = detail::quintic_rate(u) / T;
          const double yaw0 = s.foot_yaw[swing];
          s.foot[swing] = from + (next.position - from) * b;
          s.foot_velocity[swing] = (next.position - from) * db;
          // 64 u^3 (1 - u)^3: 1 at mid-swing, zero velocity and acceleration at lift-off and touch-down.
          const double w = u * (1 - u);
          s.foot[swing].z() += o.step_height * 64 * w * w * w;
          s.foot_velocity[swing].z() += o.step_height * 192 * w * w * (1 - 2 * u) / T;
          s.foot_yaw[swing] = yaw0 + (next.yaw - yaw0) * b;
          s.foot_yaw_rate[swing] = (next.yaw - yaw0) * db;
          // Outward across the foot's heading at this instant (+ left for the left foot), with the
          // lift's profile; the direction turns with the foot's yaw, hence the second rate term.
          const double side = swing == 0 ? 1.0 : -1.0, yaw = s.foot_yaw[swing];
          const Vec3<double> out(-std::sin(yaw), std::cos(yaw), 0), out_rate = Vec3<double>(-std::cos(yaw), -std::sin(yaw), 0) * s.foot_yaw_rate[swing];
          const double bump = 64 * w * w * w, bump_rate = 192 * w * w * (1 - 2 * u) / T;
          s.foot[swing] += side * o.swing_bulge * bump * out;
          s.foot_velocity[swing] += side * o.swing_bulge * (bump_rate * out + bump * out_rate);
        }
      } else if (walking >= 0) {
        // The walk is over: the ZMP goes from the last stance foot back between the feet, over
        // one double support, and stays.
        const double after = walking - steps_total * o.step_time;
        const Vec3<double>& last_stance = s.foot[1 - steps_.back().foot];
        zmp = last_stance + (0.5 * (s.foot[0] + s.foot[1]) - last_stance) * std::min(1.0, after / std::max(o.double_support, 1e-9));
      }
      s.zmp = zmp;
      zmp_x[static_cast<std::size_t>(k)] = zmp.x();
      zmp_y[static_cast<std::size_t>(k)] = zmp.y();
    }
    smooth_heading();
    const std::vector<double> cx = bounded_lipm(zmp_x), cy = bounded_lipm(zmp_y);
    for (int k = 0; k < n; ++k) {
      PatternSample& s = samples_[static_cast<std::size_t>(k)];
      s.com = Vec3<double>(cx[static_cast<std::size_t>(k)], cy[static_cast<std::size_t>(k)], com0.z());
      const int a = std::max(0, k - 1), b = std::min(n - 1, k + 1);
      s.com_velocity = Vec3<double>((cx[static_cast<std::size_t>(b)] - cx[static_cast<std::size_t>(a)]) / ((b - a) * dt_),
                                    (cy[static_cast<std::size_t>(b)] - cy[static_cast<std::size_t>(a)]) / ((b - a) * dt_), 0);
    }
    // The robot's CoM need not start where the pendulum's does (over the ZMP, between the feet):
    // the difference d is blended out over the first `settle` seconds of standing with a quintic,
    // c = c_lipm + d (1 - b(t / settle)), and the ZMP moved to keep the pendulum exact,
    // p = p_lipm + d_t - d_t'' / w^2 (d_t the blended difference).
    const Vec3<double> d(com0.x() - samples_[0].com.x(), com0.y() - samples_[0].com.y(), 0);
    for (PatternSample& s : samples_) {
      const Blend b = start_blend(s.t);
      s.com += d * b.value;
      s.com_velocity += d * b.rate;
      s.zmp += d * b.value - d * b.curvature / (omega_ * omega_);
    }
  }

  /// The samples' heading and its rate: the feet's mean yaw through three centred running means
  /// of one step (a quadratic B-spline three steps wide), the walk's ends held beyond it; the
  /// rate by central differences.
  void smooth_heading() {
    const int n = static_cast<int>(samples_.size());
    const auto at = [](std::vector<double>& x, int k) -> double& { return x[static_cast<std::size_t>(k)]; };
    std::vector<double> heading(static_cast<std::size_t>(n)), prefix(static_cast<std::size_t>(n) + 1), mean(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) at(heading, k) = 0.5 * (samples_[static_cast<std::size_t>(k)].foot_yaw[0] + samples_[static_cast<std::size_t>(k)].foot_yaw[1]);
    const int half = std::max(1, static_cast<int>(std::lround(0.5 * options_.step_time / dt_)));
    for (int pass = 0; pass < 3; ++pass) {
      prefix[0] = 0;
      for (int k = 0; k < n; ++k) at(prefix, k + 1) = at(prefix, k) + at(heading, k);
      for (int k = 0; k < n; ++k) {
        const int lo = k - half, hi = k + half, a = std::max(lo, 0), b = std::min(hi, n - 1);
        at(mean, k) = (at(prefix, b + 1) - at(prefix, a) + (a - lo) * at(heading, 0) + (hi - b) * at(heading, n - 1)) / (2 * half + 1);
      }
      heading.swap(mean);
    }
    for (int k = 0; k < n; ++k) {
      const int a = std::max(0, k - 1), b = std::min(n - 1, k + 1);
      PatternSample& s = samples_[static_cast<std::size_t>(k)];
      s.heading = at(heading, k);
      s.heading_rate = (at(heading, b) - at(heading, a)) / ((b - a) * dt_);
    }
  }

  /// 1 - b(t / settle) with b the quintic blend, settle = 0.8 start_time, and its first two
  /// derivatives: 1 at the start, 0 from `settle` on (1 throughout without a standing start: the
  /// CoM's offset from the pendulum's is then kept, not blended out).
  struct Blend {
    double value = 0, rate = 0, curvature = 0;
  };
  Blend start_blend(double t) const {
    const double settle = 0.8 * options_.start_time;
    if (!(settle > 0)) return {1, 0, 0};
    if (t >= settle) return {};
    const double u = t / settle;
    return {1 - detail::quintic(u), -detail::quintic_rate(u) / settle, -60 * u * (1 - u) * (1 - 2 * u) / (settle * settle)};
  }

  /// The bounded LIPM solution c = (w/2) exp(-w|t|) * p on the grid: forward and backward
  /// recursions, p piecewise linear between samples and constant beyond the ends.
  std::vector<double> bounded_lipm(const std::vector<double>& p) const {
    const std::size_t n = p.size();
    const double a = std::exp(-omega_ * dt_);
    // Exact convolution of a linear segment with exp(-w t) over one step: weights on its ends.
    const double wt = omega_ * dt_;
    const double w_near = (1 - a) / wt - a, w_far = 1 - (1 - a) / wt;  // sum to 1 - a
    std::vector<double> forward(n), backward(n), c(n);
    forward[0] = p[0];  // p constant before the start: the filter at rest
    for (std::size_t k = 1; k < n; ++k) forward[k] = a * forward[k - 1] + w_far * p[k] + w_near * p[k - 1];
    backward[n - 1] = p[n - 1];
    for (std::size_t k = n - 1; k-- > 0;) backward[k] = a * backward[k + 1] + w_far * p[k] + w_near * p[k + 1];
    for (std::size_t k = 0; k < n; ++k) c[k] = 0.5 * (forward[k] + backward[k]);
    return c;
  }

  PatternOptions options_;
  double dt_, omega_ = 1, duration_ = 0;
  std::vector<Footstep> steps_;
  std::vector<PatternSample> samples_;
};

}  // namespace mbgen::walking
