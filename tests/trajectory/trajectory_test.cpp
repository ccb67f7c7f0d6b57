// Trajectory evaluation and sampling: any time, sample grid, heading (eq. 8) against the velocity
// direction. (WGS84 samples and the CSV: tests/service/geo_samples_test.cpp.)
#include <cmath>

#include <gtest/gtest.h>

#include "tests/trajectory/random_paths.hpp"
#include "trajectory/trajectory_builder.hpp"

namespace skyroute {
namespace {

double angleDiffDeg(double a, double b) {
  double d = std::fmod(std::abs(a - b), 360.0);
  return std::min(d, 360.0 - d);
}

Trajectory built(const std::vector<Eigen::Vector3d>& w) {
  auto b = buildTrajectory(w, VehicleLimits{});
  EXPECT_TRUE(b.ok());
  return b->trajectory;
}

TEST(Trajectory, EvaluatesAnyTimeAndClamps) {
  const auto w = testing::randomWalk(8, 10);
  const Trajectory t = built(w);
  ASSERT_FALSE(t.empty());
  EXPECT_EQ(t.knotTimes().front(), 0.0);
  EXPECT_NEAR(t.duration_s(), t.knotTimes().back(), 1e-12);
  EXPECT_LT((t.evaluate(0.0, Derivative::kPosition) - w.front()).norm(), 1e-6);
  EXPECT_LT((t.evaluate(t.duration_s(), Derivative::kPosition) - w.back()).norm(), 1e-6);
  EXPECT_EQ(t.evaluate(-5.0, Derivative::kPosition), t.evaluate(0.0, Derivative::kPosition));
  EXPECT_EQ(t.evaluate(t.duration_s() + 5.0, Derivative::kPosition), t.evaluate(t.duration_s(), Derivative::kPosition));
  const TrajectoryState s = t.stateAt(0.37 * t.duration_s());
  EXPECT_EQ(s.velocity_mps, t.evaluate(0.37 * t.duration_s(), Derivative::kVelocity));
  EXPECT_EQ(s.jerk_mps3, t.evaluate(0.37 * t.duration_s(), Derivative::kJerk));
  EXPECT_TRUE(Trajectory().sample(0.1).empty());
  EXPECT_EQ(Trajectory().evaluate(1.0, Derivative::kPosition), Eigen::Vector3d::Zero());
}

TEST(Trajectory, SamplesOnTheGridAndEndsAtTheEnd) {
  const Trajectory t = built(testing::randomWalk(9, 6));
  const double dt = 0.1;
  const auto samples = t.sample(dt);
  ASSERT_GE(samples.size(), 2u);
  EXPECT_EQ(samples.front().time_s, 0.0);
  EXPECT_DOUBLE_EQ(samples.back().time_s, t.duration_s());
  for (std::size_t i = 1; i + 1 < samples.size(); ++i) EXPECT_NEAR(samples[i].time_s - samples[i - 1].time_s, dt, 1e-9);
  EXPECT_LE(samples.back().time_s - samples[samples.size() - 2].time_s, dt + 1e-9);
  EXPECT_TRUE(t.sample(0.0).empty());
  EXPECT_TRUE(t.sample(std::nan("")).empty());
}

TEST(Trajectory, HeadingFollowsEquation8AndTheVelocity) {
  // Due east, then due north: 90 then 0 degrees.
  const Trajectory east = built({{0, 0, 100}, {1000, 0, 100}});
  for (const auto& s : east.sample(0.5)) EXPECT_NEAR(s.heading_deg, 90.0, 1e-6);
  EXPECT_NEAR(east.stateAt(0.0).heading_deg, 90.0, 1e-6);  // at rest: where it is about to go
  const Trajectory north = built({{0, 0, 100}, {0, 1000, 100}});
  for (const auto& s : north.sample(0.5)) EXPECT_LT(angleDiffDeg(s.heading_deg, 0.0), 1e-6);
  const Trajectory sw = built({{0, 0, 100}, {-500, -500, 100}});
  EXPECT_NEAR(sw.stateAt(3.0).heading_deg, 225.0, 1e-6);
  // On a curvy path, eq. 8 on 0.05 s samples is the chord's direction: it agrees with the
  // velocity direction at the middle of the step (to second order) wherever the vehicle moves.
  const Trajectory curvy = built(testing::randomWalk(12, 12));
  const double dt = 0.05;
  const auto samples = curvy.sample(dt);
  for (std::size_t i = 0; i + 2 < samples.size(); ++i) {
    const Eigen::Vector3d v = curvy.evaluate(samples[i].time_s + 0.5 * dt, Derivative::kVelocity);
    if (std::hypot(v.x(), v.y()) < 2.0) continue;
    const double from_velocity = compassHeadingDeg(v.x(), v.y());
    EXPECT_LT(angleDiffDeg(samples[i].heading_deg, from_velocity), 0.1) << "t=" << samples[i].time_s;
  }
  EXPECT_EQ(samples.back().heading_deg, samples[samples.size() - 2].heading_deg);  // psi_M = psi_{M-1}
  // Eq. 9 at the joints: times and positions of the knots, heading from the next knot.
  const auto w = std::vector<Eigen::Vector3d>{{0, 0, 100}, {500, 0, 120}, {500, 700, 140}, {-100, 700, 100}};
  TrajectoryOptions no_extra;
  no_extra.waypoint_spacing_m = 0.0;
  auto b = buildTrajectory(w, VehicleLimits{}, no_extra);
  ASSERT_TRUE(b.ok());
  const auto knots = b->trajectory.knotStates();
  ASSERT_EQ(knots.size(), w.size());
  const double expected[] = {90.0, 0.0, 270.0, 270.0};
  for (std::size_t j = 0; j < knots.size(); ++j) {
    EXPECT_LT((knots[j].position_m - w[j]).norm(), 1e-6);
    EXPECT_NEAR(knots[j].time_s, b->trajectory.knotTimes()[j], 1e-12);
    EXPECT_LT(angleDiffDeg(knots[j].heading_deg, expected[j]), 1e-6) << j;
  }
}

}  // namespace
}  // namespace skyroute
