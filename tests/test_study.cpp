// The study's own measuring tools (examples/study/): the step ladder and the bisection of the
// stability map, and the trajectory deviation (docs/study.md).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "examples/study/stability_map.hpp"
#include "examples/study/trajectory.hpp"

namespace mbgen::study {
namespace {

TEST(StudyTest, LadderHasFourStepsPerDecade) {
  const std::vector<double> ladder = step_ladder(1e-5, 1e-3);
  ASSERT_EQ(ladder.size(), 9u);
  EXPECT_DOUBLE_EQ(ladder.front(), 1e-5);
  EXPECT_DOUBLE_EQ(ladder.back(), 1e-3);
  for (std::size_t k = 1; k < ladder.size(); ++k) EXPECT_NEAR(ladder[k] / ladder[k - 1], std::pow(10.0, 0.25), 1e-12);
}

/// A scenario stable up to `limit`, failing above it with `diverged` at t = h (so the failure
/// recorded can be traced to the run that produced it).
struct Threshold {
  double limit;
  int calls = 0;
  bool operator()(double h, sim::StepStatus& status, double& time) {
    ++calls;
    const bool ok = h <= limit;
    status = ok ? sim::StepStatus::ok : sim::StepStatus::diverged;
    time = h;
    return ok;
  }
};

TEST(StudyTest, BisectionFindsTheLargestStableRungAndTheFailureAboveIt) {
  const std::vector<double> ladder = step_ladder(1e-5, 1e-3);
  Threshold t{4e-4};
  const StabilityResult r = largest_stable_step(ladder, std::ref(t));
  EXPECT_NEAR(r.stable, std::pow(10.0, -3.5), 1e-15);  // 3.16e-4 <= 4e-4 < 5.62e-4
  EXPECT_NEAR(r.unstable, std::pow(10.0, -3.25), 1e-15);
  EXPECT_EQ(r.failure, sim::StepStatus::diverged);
  EXPECT_DOUBLE_EQ(r.failure_time, r.unstable);  // the failure reported is the one at `unstable`
  EXPECT_EQ(r.runs, t.calls);
  EXPECT_LE(r.runs, 2 + 4);  // top, bottom, then log2(9) rounded up
}

TEST(StudyTest, BisectionReportsAllStableAndNoneStable) {
  const std::vector<double> ladder = step_ladder(1e-5, 1e-3);
  Threshold all{1.0};
  const StabilityResult a = largest_stable_step(ladder, std::ref(all));
  EXPECT_DOUBLE_EQ(a.stable, 1e-3);
  EXPECT_EQ(a.unstable, 0.0);
  EXPECT_EQ(a.runs, 1);
  Threshold none{1e-9};
  const StabilityResult n = largest_stable_step(ladder, std::ref(none));
  EXPECT_EQ(n.stable, 0.0);
  EXPECT_DOUBLE_EQ(n.unstable, 1e-5);
  EXPECT_EQ(n.runs, 2);
}

/// A floating-base trajectory of two samples with base position, yaw and two joints.
Trajectory floating(double x, double yaw, double j1, double j2) {
  Trajectory t;
  for (int k = 0; k < 2; ++k) {
    VecX<double> q(9);
    q << x, 0, 0, 0, 0, std::sin(yaw / 2), std::cos(yaw / 2), j1, j2;
    t.q.push_back(q);
  }
  return t;
}

TEST(StudyTest, DeviationMeasuresTinyRotationsExactly) {
  // 1e-10 rad: 2 acos(q . r) would read ~1.5e-8 (round-off of a dot product near 1).
  const Deviation d = deviation(floating(0, 1e-10, 0, 0), floating(0, 0, 0, 0), true);
  EXPECT_NEAR(d.base_orientation, 1e-10, 1e-20);
  EXPECT_EQ(d.base_position, 0.0);
  // q and -q are the same attitude.
  Trajectory flipped = floating(0, 0.3, 0, 0);
  for (VecX<double>& q : flipped.q) q.segment<4>(3) *= -1;
  EXPECT_NEAR(deviation(flipped, floating(0, 0.3, 0, 0), true).base_orientation, 0.0, 1e-15);
  EXPECT_NEAR(deviation(floating(0, 0.3, 0, 0), floating(0, 0, 0, 0), true).base_orientation, 0.3, 1e-14);
}

TEST(StudyTest, DeviationNamesTheWorstJointAndComparesCommonSamplesOnly) {
  Trajectory a = floating(0.5, 0, 0.1, -0.2), b = floating(0.25, 0, 0.1, 0.3);
  const Deviation d = deviation(a, b, true);
  EXPECT_DOUBLE_EQ(d.base_position, 0.25);
  EXPECT_DOUBLE_EQ(d.joints, 0.5);
  EXPECT_EQ(d.worst_joint_q, 8);
  EXPECT_DOUBLE_EQ(d.largest(), 0.5);
  b.q.resize(1);
  b.q[0][8] = 10;  // a later sample the shorter run never reached is not compared
  a.q[1][8] = -100;
  EXPECT_DOUBLE_EQ(deviation(a, b, true).joints, 10.2);
}

}  // namespace
}  // namespace mbgen::study
