// The walking pattern of mbgen_walk (mbgen/control/walking_pattern.hpp): the CoM obeys the
// linear inverted pendulum for the ZMP it was made from (central second differences against
// w^2 (c - p)), the swing feet move continuously with the velocities the pattern states (against
// finite differences), land on their footsteps with zero velocity, and the footsteps alternate;
// the swing's outward bulge moves nothing else; the heading turns steadily.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mbgen/control/walking_pattern.hpp"

namespace mbgen::test {
namespace {

using walking::PatternOptions;
using walking::WalkingPattern;

const Vec3<double> kLeft(0.0, 0.09, 0.0), kRight(0.0, -0.09, 0.0), kCom(0.05, 0.01, 0.9);  // the CoM off the feet's middle

TEST(WalkingPattern, TheCentreOfMassObeysTheInvertedPendulum) {
  for (double turn : {0.0, 0.15}) {
    PatternOptions o;
    o.turn_per_step = turn;
    const double dt = 1e-3;
    const WalkingPattern p(kLeft, kRight, kCom, o, dt);
    const double w2 = p.omega() * p.omega();
    ASSERT_NEAR(w2, 9.81 / 0.9, 1e-12);
    double worst = 0, scale = 0;
    for (int k = 1; k + 1 < p.samples(); ++k) {
      const auto &a = p.sample(k - 1), &b = p.sample(k), &c = p.sample(k + 1);
      const Vec3<double> cdd = (c.com - 2 * b.com + a.com) / (dt * dt);
      const Vec3<double> lipm = w2 * (b.com - b.zmp);
      worst = std::max(worst, (cdd - lipm).head<2>().norm());
      scale = std::max(scale, lipm.head<2>().norm());
    }
    std::printf("  turn %.2f: |c'' - w^2 (c - p)| <= %.1e m/s^2 (largest w^2 |c - p| %.2f)\n", turn, worst, scale);
    EXPECT_LT(worst, 1e-2 * scale);  // central differences at the ZMP's kinks: O(dt) of its rate
    // The CoM starts where the robot's is; its offset from the pendulum's is blended out in the
    // first 0.4 s, after which the ZMP is the pattern's own: between the feet until the first step.
    const int settled = static_cast<int>(0.41 / dt), stepping = static_cast<int>(0.49 / dt);
    for (int k = settled; k < stepping; ++k) EXPECT_LT((p.sample(k).zmp - 0.5 * (kLeft + kRight)).norm(), 1e-12) << k;
    // And ends over the middle of the feet.
    const auto& end = p.sample(p.samples() - 1);
    EXPECT_LT((end.com - 0.5 * (end.foot[0] + end.foot[1])).head<2>().norm(), 0.02);
    EXPECT_LT((p.sample(0).com - kCom).norm(), 1e-12);
  }
}

TEST(WalkingPattern, SwingFeetMoveAsTheirVelocitiesSayAndLandOnTheirSteps) {
  PatternOptions o;
  o.turn_per_step = 0.15;
  const double dt = 1e-3;
  const WalkingPattern p(kLeft, kRight, kCom, o, dt);
  double worst = 0, worst_yaw = 0, highest = 0;
  for (int k = 1; k + 1 < p.samples(); ++k)
    for (int f = 0; f < 2; ++f) {
      const Vec3<double> fd = (p.sample(k + 1).foot[f] - p.sample(k - 1).foot[f]) / (2 * dt);
      worst = std::max(worst, (fd - p.sample(k).foot_velocity[f]).norm());
      worst_yaw = std::max(worst_yaw, std::abs((p.sample(k + 1).foot_yaw[f] - p.sample(k - 1).foot_yaw[f]) / (2 * dt) -
                                               p.sample(k).foot_yaw_rate[f]));
      highest = std::max(highest, p.sample(k).foot[f].z());
    }
  std::printf("  swing foot velocity vs central differences %.1e m/s, yaw rate %.1e rad/s; clearance %.3f m\n", worst, worst_yaw, highest);
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(worst_yaw, 1e-3);
  EXPECT_NEAR(highest, o.step_height, 1e-4);
  // Footsteps: the two standing feet, one per step alternating from first_foot, one to close.
  const auto& steps = p.footsteps();
  ASSERT_EQ(static_cast<int>(steps.size()), 2 + o.steps + 1);
  for (std::size_t i = 2; i < steps.size(); ++i) EXPECT_EQ(steps[i].foot, (o.first_foot + static_cast<int>(i) - 2) % 2);
  // At the end each foot stands on its last footstep.
  const auto& end = p.sample(p.samples() - 1);
  for (int f = 0; f < 2; ++f) {
    const auto& last = *std::find_if(steps.rbegin(), steps.rend(), [&](const walking::Footstep& s) { return s.foot == f; });
    EXPECT_LT((end.foot[f] - last.position).norm(), 1e-12);
    EXPECT_NEAR(end.foot_yaw[f], last.yaw, 1e-12);
    EXPECT_EQ(end.foot_velocity[f].norm(), 0.0);
  }
}

// correct_com answers a ZMP error e by the CoM change dc the pendulum needs to cancel it,
// dc - dc'' / w^2 = -e (central second differences), once the start has settled; dc is zero at
// the start (the robot starts at rest there), the stated CoM velocity is the CoM's rate, and the
// reference ZMP and feet do not move.
TEST(WalkingPattern, TheCentreOfMassCorrectionCancelsAZmpError) {
  PatternOptions o;
  o.turn_per_step = 0.15;
  const double dt = 1e-3;
  const WalkingPattern before(kLeft, kRight, kCom, o, dt);
  WalkingPattern after = before;
  std::vector<Eigen::Vector2d> error(static_cast<std::size_t>(before.samples()));
  for (int k = 0; k < before.samples(); ++k) {
    const double t = before.sample(k).t;  // a smooth error at the step frequency, as a swing leg's
    error[static_cast<std::size_t>(k)] = Eigen::Vector2d(0.1 * std::sin(2 * M_PI * 1.25 * t), 0.03 * std::cos(2 * M_PI * 1.25 * t + 0.3));
  }
  after.correct_com(error);
  const double w2 = before.omega() * before.omega();
  double worst = 0, worst_velocity = 0, largest = 0;
  for (int k = 1; k + 1 < before.samples(); ++k) {
    const auto dc = [&](int j) { return Eigen::Vector2d((after.sample(j).com - before.sample(j).com).head<2>()); };
    const Eigen::Vector2d residual = dc(k) - (dc(k + 1) - 2 * dc(k) + dc(k - 1)) / (dt * dt) / w2 + error[static_cast<std::size_t>(k)];
    if (before.settled(before.sample(k - 1).t) == 1) worst = std::max(worst, residual.norm());
    largest = std::max(largest, dc(k).norm());
    const Eigen::Vector2d rate = (dc(k + 1) - dc(k - 1)) / (2 * dt);
    worst_velocity = std::max(worst_velocity, (rate - (after.sample(k).com_velocity - before.sample(k).com_velocity).head<2>()).norm());
    EXPECT_EQ(after.sample(k).zmp, before.sample(k).zmp);
    EXPECT_EQ(after.sample(k).foot[0], before.sample(k).foot[0]);
  }
  std::printf("  |dc - dc''/w^2 + e| <= %.1e m after the start (|e| <= 0.1 m, |dc| <= %.3f m); its velocity vs differences %.1e m/s\n",
              worst, largest, worst_velocity);
  EXPECT_LT(worst, 2e-6);  // 2e-5 of |e|: the piecewise-linear convolution and the differences on the 1 ms grid
  EXPECT_GT(largest, 1e-3);  // the correction does move the CoM
  EXPECT_LT(worst_velocity, 1e-12);
  EXPECT_EQ(after.sample(0).com, before.sample(0).com);
  EXPECT_EQ(before.settled(0.0), 0.0);
  EXPECT_EQ(before.settled(0.8 * o.start_time), 1.0);
  EXPECT_THROW(after.correct_com(std::vector<Eigen::Vector2d>(3)), std::invalid_argument);
}

// yaw_free_momentum: for the pendulum's own CoM the ground force points along c - p, so no
// vertical angular momentum is needed (zero up to the differences at the ZMP's kinks); for a
// corrected CoM its rate is the force's moment m ((p - c) x c'')_z about the CoM, less the
// constant that brings it back to zero at the end; zero at the start.
TEST(WalkingPattern, YawFreeMomentumBalancesTheGroundForcesMoment) {
  PatternOptions o;
  o.turn_per_step = 0.15;
  const double dt = 1e-3, mass = 60.0;
  WalkingPattern p(kLeft, kRight, kCom, o, dt);
  const std::vector<double> pendulum = p.yaw_free_momentum(mass);
  std::vector<Eigen::Vector2d> error(static_cast<std::size_t>(p.samples()));
  for (int k = 0; k < p.samples(); ++k)
    error[static_cast<std::size_t>(k)] = Eigen::Vector2d(0.1 * std::sin(2 * M_PI * 1.25 * p.sample(k).t), 0.03 * std::cos(2 * M_PI * 1.25 * p.sample(k).t));
  p.correct_com(error);
  const std::vector<double> k = p.yaw_free_momentum(mass);
  const int n = p.samples();
  double largest = 0, largest_pendulum = 0, worst_rate = 0, drift = 0;
  for (int i = 0; i < n; ++i) largest = std::max(largest, std::abs(k[static_cast<std::size_t>(i)]));
  for (double x : pendulum) largest_pendulum = std::max(largest_pendulum, std::abs(x));
  const double begin = o.start_time, end = p.duration() - o.end_time;
  const auto moment = [&](int i) {
    const Vec3<double> cdd = (p.sample(i + 1).com - 2 * p.sample(i).com + p.sample(i - 1).com) / (dt * dt);
    const Vec3<double> r = p.sample(i).zmp - p.sample(i).com;
    return mass * (r.x() * cdd.y() - r.y() * cdd.x());
  };
  // Over the steps the rate is the moment less one constant (what brings k_z back to zero at the
  // end), measured at the first sample and held to round-off at every other.
  bool first = true;
  for (int i = 2; i + 2 < n; ++i) {
    const double t = p.sample(i).t;
    if (t <= begin + 2 * dt || t >= end - 2 * dt) continue;
    const double rate = (k[static_cast<std::size_t>(i + 1)] - k[static_cast<std::size_t>(i - 1)]) / (2 * dt);
    const double trapezoid = (moment(i - 1) + 2 * moment(i) + moment(i + 1)) / 4;  // the rule's rate over two samples
    if (first) drift = rate - trapezoid, first = false;
    worst_rate = std::max(worst_rate, std::abs(rate - trapezoid - drift));
  }
  std::printf("  pendulum CoM: |k_z| <= %.1e; corrected: |k_z| <= %.3f kg m^2/s, its rate vs the force's moment %.1e N m "
              "(less the constant %.1e N m)\n",
              largest_pendulum, largest, worst_rate, drift);
  EXPECT_LT(largest_pendulum, 1e-3 * largest);
  EXPECT_GT(largest, 0.01);
  EXPECT_LT(worst_rate, 1e-9 * mass);
  EXPECT_EQ(k.front(), 0.0);
  EXPECT_NEAR(k.back(), 0.0, 1e-12);
  EXPECT_THROW(p.yaw_free_momentum(-1.0), std::invalid_argument);
  EXPECT_THROW(p.yaw_free_momentum(std::nan("")), std::invalid_argument);
}

// swing_bulge bends each swing outward by that much at mid-swing and nowhere else: against the
// same pattern without it, the left foot only ever moves left, the right only right (in the
// foot's heading), by at most the bulge, reached; the stance feet, the footsteps and the CoM do
// not move; the velocities stay the positions' rates (the test above, repeated with a bulge).
TEST(WalkingPattern, TheSwingBulgesOutwardAndNothingElseMoves) {
  PatternOptions o;
  o.turn_per_step = 0.15;
  const double dt = 1e-3;
  const WalkingPattern straight(kLeft, kRight, kCom, o, dt);
  o.swing_bulge = 0.03;
  const WalkingPattern bent(kLeft, kRight, kCom, o, dt);
  double largest = 0, inward = 0, other = 0, worst_rate = 0;
  for (int k = 1; k + 1 < bent.samples(); ++k)
    for (int f = 0; f < 2; ++f) {
      const auto &a = straight.sample(k), &b = bent.sample(k);
      const Vec3<double> d = b.foot[f] - a.foot[f];
      const Vec3<double> out = (f == 0 ? 1.0 : -1.0) * Vec3<double>(-std::sin(b.foot_yaw[f]), std::cos(b.foot_yaw[f]), 0);
      largest = std::max(largest, d.dot(out));
      inward = std::max(inward, -d.dot(out));
      other = std::max(other, (d - d.dot(out) * out).norm());
      if (b.stance == f || b.stance < 0) other = std::max(other, d.norm());
      other = std::max(other, (b.com - a.com).norm());
      const Vec3<double> fd = (bent.sample(k + 1).foot[f] - bent.sample(k - 1).foot[f]) / (2 * dt);
      worst_rate = std::max(worst_rate, (fd - b.foot_velocity[f]).norm());
    }
  std::printf("  bulge 0.03 m: outward at most %.4f m, inward %.1e, any other motion %.1e m; velocity vs differences %.1e m/s\n", largest,
              inward, other, worst_rate);
  EXPECT_NEAR(largest, 0.03, 1e-5);
  EXPECT_LT(inward, 1e-15);
  EXPECT_LT(other, 1e-15);
  EXPECT_LT(worst_rate, 1e-3);
}

// The heading: the feet's mean yaw smoothed over a step. It starts at the standing yaw and ends at
// the last footsteps' (the turn is complete), never leaves the mean's range, turns at the rate it
// states, and turns steadily: its rate peaks at less than half of the mean yaw's (which pulses,
// one pulse per swing) and changes by little from one sample to the next.
TEST(WalkingPattern, TheHeadingTurnsSteadilyWhereTheFeetTurnInPulses) {
  PatternOptions o;
  o.turn_per_step = 0.15;
  const double dt = 1e-3;
  const WalkingPattern p(kLeft, kRight, kCom, o, dt);
  double raw_peak = 0, peak = 0, worst_rate = 0, largest_change = 0, lowest = 1e9, highest = -1e9;
  for (int k = 1; k + 1 < p.samples(); ++k) {
    const auto& s = p.sample(k);
    raw_peak = std::max(raw_peak, std::abs(0.5 * (s.foot_yaw_rate[0] + s.foot_yaw_rate[1])));
    peak = std::max(peak, std::abs(s.heading_rate));
    worst_rate = std::max(worst_rate, std::abs((p.sample(k + 1).heading - p.sample(k - 1).heading) / (2 * dt) - s.heading_rate));
    largest_change = std::max(largest_change, std::abs(s.heading_rate - p.sample(k - 1).heading_rate));
    lowest = std::min(lowest, s.heading);
    highest = std::max(highest, s.heading);
  }
  const auto& first = p.sample(0);
  const auto& last = p.sample(p.samples() - 1);
  const double final_yaw = 0.5 * (last.foot_yaw[0] + last.foot_yaw[1]);
  std::printf("  heading: peak rate %.3f rad/s against the feet's mean yaw's %.3f; largest change of rate per sample %.1e rad/s\n", peak,
              raw_peak, largest_change);
  EXPECT_NEAR(final_yaw, o.steps * o.turn_per_step, 1e-12);
  EXPECT_NEAR(first.heading, 0.0, 1e-9);  // the kernel (1.2 s wide) reaches back past the 0.5 s standing start: its tail
  EXPECT_NEAR(last.heading, final_yaw, 1e-9);
  EXPECT_GE(lowest, -1e-12);
  EXPECT_LE(highest, final_yaw + 1e-12);
  EXPECT_LT(worst_rate, 1e-9);
  EXPECT_LT(peak, 0.5 * raw_peak);
  EXPECT_LT(largest_change, 1e-2 * peak);
}

TEST(WalkingPattern, BadOptionsAreRefused) {
  PatternOptions o;
  o.double_support = o.step_time;
  EXPECT_THROW(WalkingPattern(kLeft, kRight, kCom, o, 1e-3), std::invalid_argument);
  o = PatternOptions{};
  EXPECT_THROW(WalkingPattern(kLeft, kRight, kCom, o, 0.0), std::invalid_argument);
  o.steps = 0;
  EXPECT_THROW(WalkingPattern(kLeft, kRight, kCom, o, 1e-3), std::invalid_argument);
}

}  // namespace
}  // namespace mbgen::test
