// The walking pattern of mbgen_walk (examples/walking/walking_pattern.hpp): the CoM obeys the
// linear inverted pendulum for the ZMP it was made from (central second differences against
// w^2 (c - p)), the swing feet move continuously with the velocities the pattern states (against
// finite differences), land on their footsteps with zero velocity, and the footsteps alternate.
#include <gtest/gtest.h>

#include <cmath>

#include "examples/walking/walking_pattern.hpp"

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
