// Minimum-snap degree-7 spline: interpolation, continuity up to jerk at every joint on random seeded
// waypoint sets (checked numerically from both sides), the optimality conditions (continuity of
// snap and beyond), rest-to-rest and given end states, optimum against an independent dense KKT
// solve in another parameterisation, and against naive alternatives.
#include <cmath>
#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "tests/trajectory/random_paths.hpp"
#include "trajectory/spline7.hpp"
#include "trajectory/time_allocation.hpp"
#include "trajectory/trajectory.hpp"

namespace skyroute {
namespace {

std::vector<double> eq3Durations(const std::vector<Eigen::Vector3d>& w, double v_ref) {
  std::vector<double> d;
  for (std::size_t i = 1; i < w.size(); ++i) d.push_back((w[i] - w[i - 1]).norm() / v_ref);
  return d;
}

// Largest magnitude of derivative n over all joints (scale for relative tolerances).
double jointScale(const std::vector<Segment>& segments, int n) {
  double scale = 0.0;
  for (const Segment& s : segments)
    for (double tau : {0.0, 1.0})
      for (const Polynomial7& p : s.axes) scale = std::max(scale, std::abs(p.evaluateTime(tau, n, s.duration_s)));
  return scale;
}

// max over joints and axes of |left limit - right limit| of derivative n, relative to its scale.
double worstJointJump(const std::vector<Segment>& segments, int n) {
  const double scale = jointScale(segments, n) + 1e-12;
  double worst = 0.0;
  for (std::size_t s = 0; s + 1 < segments.size(); ++s)
    for (int axis = 0; axis < 3; ++axis) {
      const double left = segments[s].axes[axis].evaluateTime(1.0, n, segments[s].duration_s);
      const double right = segments[s + 1].axes[axis].evaluateTime(0.0, n, segments[s + 1].duration_s);
      worst = std::max(worst, std::abs(left - right) / scale);
    }
  return worst;
}

TEST(Spline7, ContinuousUpToJerkAtEveryJointOnRandomSets) {
  for (unsigned seed = 1; seed <= 25; ++seed) {
    const auto waypoints = testing::randomWalk(seed, 3 + static_cast<int>(seed % 40));
    const auto durations = eq3Durations(waypoints, 50.0);
    auto segments = solveMinimumSnapSpline(waypoints, durations);
    ASSERT_TRUE(segments.ok()) << segments.error().describe();
    ASSERT_EQ(segments->size(), waypoints.size() - 1);
    // Passes through every waypoint (both segments at a joint).
    for (std::size_t s = 0; s < segments->size(); ++s) {
      const Segment& seg = (*segments)[s];
      EXPECT_LT((seg.evaluate(0.0, Derivative::kPosition) - waypoints[s]).norm(), 1e-6) << "seed " << seed;
      EXPECT_LT((seg.evaluate(seg.duration_s, Derivative::kPosition) - waypoints[s + 1]).norm(), 1e-6);
    }
    for (int n = 0; n <= 3; ++n) EXPECT_LT(worstJointJump(*segments, n), 1e-8) << "seed " << seed << " order " << n;
  }
}

TEST(Spline7, ContinuityHoldsThroughTrajectoryEvaluationAcrossJoints) {
  // Independent of the segment structure: evaluate the trajectory just before and after each joint
  // time; a jump in position..jerk would show as a difference far larger than the slope * eps.
  const auto waypoints = testing::randomWalk(99, 30);
  auto segments = solveMinimumSnapSpline(waypoints, eq3Durations(waypoints, 40.0));
  ASSERT_TRUE(segments.ok());
  const Trajectory trajectory(*segments);
  const double eps = 1e-7;
  for (std::size_t j = 1; j + 1 < trajectory.knotTimes().size(); ++j) {
    const double t = trajectory.knotTimes()[j];
    for (Derivative d : {Derivative::kPosition, Derivative::kVelocity, Derivative::kAcceleration, Derivative::kJerk}) {
      const Eigen::Vector3d before = trajectory.evaluate(t - eps, d);
      const Eigen::Vector3d after = trajectory.evaluate(t + eps, d);
      const Eigen::Vector3d next = trajectory.evaluate(t + eps, static_cast<Derivative>(order(d) + 1));
      EXPECT_LT((after - before).norm(), 4 * eps * (1.0 + next.norm()) + 1e-9)
          << "joint " << j << " " << to_string(d);
    }
  }
}

TEST(Spline7, MinimumSnapIsContinuousUpToSixthDerivative) {
  // Euler-Lagrange: at the optimum, snap, crackle and pop are continuous too. The solver does not
  // impose that, so it checks the optimisation itself.
  for (unsigned seed = 100; seed < 110; ++seed) {
    const auto waypoints = testing::randomWalk(seed, 12);
    auto segments = solveMinimumSnapSpline(waypoints, eq3Durations(waypoints, 30.0));
    ASSERT_TRUE(segments.ok());
    for (int n = 4; n <= 6; ++n) EXPECT_LT(worstJointJump(*segments, n), 1e-6) << "seed " << seed << " order " << n;
  }
}

TEST(Spline7, RestToRestByDefaultAndGivenEndStates) {
  const auto waypoints = testing::randomWalk(5, 8);
  const auto durations = eq3Durations(waypoints, 25.0);
  auto rest = solveMinimumSnapSpline(waypoints, durations);
  ASSERT_TRUE(rest.ok());
  const Segment& first = rest->front();
  const Segment& last = rest->back();
  for (Derivative d : {Derivative::kVelocity, Derivative::kAcceleration, Derivative::kJerk}) {
    EXPECT_LT(first.evaluate(0.0, d).norm(), 1e-9) << to_string(d);
    EXPECT_LT(last.evaluate(last.duration_s, d).norm(), 1e-9) << to_string(d);
  }
  SplineBoundary boundary;
  boundary.start.velocity_mps = {20.0, -5.0, 1.0};
  boundary.start.acceleration_mps2 = {0.5, 0.0, -0.2};
  boundary.start.jerk_mps3 = {0.0, 0.1, 0.0};
  boundary.end.velocity_mps = {-10.0, 15.0, 0.0};
  auto given = solveMinimumSnapSpline(waypoints, durations, boundary);
  ASSERT_TRUE(given.ok());
  EXPECT_LT((given->front().evaluate(0.0, Derivative::kVelocity) - boundary.start.velocity_mps).norm(), 1e-9);
  EXPECT_LT((given->front().evaluate(0.0, Derivative::kAcceleration) - boundary.start.acceleration_mps2).norm(), 1e-9);
  EXPECT_LT((given->front().evaluate(0.0, Derivative::kJerk) - boundary.start.jerk_mps3).norm(), 1e-9);
  const Segment& end = given->back();
  EXPECT_LT((end.evaluate(end.duration_s, Derivative::kVelocity) - boundary.end.velocity_mps).norm(), 1e-9);
  EXPECT_LT(end.evaluate(end.duration_s, Derivative::kAcceleration).norm(), 1e-9);
}

TEST(Spline7, SingleSegmentIsTheHermitePolynomial) {
  const std::vector<Eigen::Vector3d> w{{0, 0, 100}, {300, 400, 150}};
  auto segments = solveMinimumSnapSpline(w, {10.0});
  ASSERT_TRUE(segments.ok());
  ASSERT_EQ(segments->size(), 1u);
  const Segment& s = segments->front();
  // Rest-to-rest septic: symmetric, so the midpoint is the midpoint of the chord.
  EXPECT_LT((s.evaluate(5.0, Derivative::kPosition) - 0.5 * (w[0] + w[1])).norm(), 1e-9);
  EXPECT_LT(s.evaluate(10.0, Derivative::kVelocity).norm(), 1e-9);
}

// Independent reference: minimise sum of integral snap^2 over coefficients in *local time*
// monomials (not tau), with every interpolation, boundary and continuity condition as an explicit
// equality constraint, by a dense KKT solve.
std::vector<Eigen::VectorXd> denseKktReference(const std::vector<Eigen::Vector3d>& w, const std::vector<double>& T) {
  const int m = static_cast<int>(T.size());
  const int n = 8 * m;
  auto ff = [](int k, int d) { return Polynomial7::fallingFactorial(k, d); };
  Eigen::MatrixXd q = Eigen::MatrixXd::Zero(n, n);
  for (int s = 0; s < m; ++s)
    for (int i = 4; i < 8; ++i)
      for (int j = 4; j < 8; ++j)
        q(8 * s + i, 8 * s + j) = ff(i, 4) * ff(j, 4) * std::pow(T[s], i + j - 7) / (i + j - 7);
  auto row = [&](int s, double t, int d) {
    Eigen::RowVectorXd r = Eigen::RowVectorXd::Zero(n);
    for (int k = d; k < 8; ++k) r(8 * s + k) = ff(k, d) * std::pow(t, k - d);
    return r;
  };
  std::vector<Eigen::RowVectorXd> rows;
  std::vector<Eigen::Vector3d> rhs;
  for (int s = 0; s < m; ++s) {
    rows.push_back(row(s, 0.0, 0));
    rhs.push_back(w[s]);
    rows.push_back(row(s, T[s], 0));
    rhs.push_back(w[s + 1]);
  }
  for (int d = 1; d <= 3; ++d) {
    rows.push_back(row(0, 0.0, d));
    rhs.push_back(Eigen::Vector3d::Zero());
    rows.push_back(row(m - 1, T[m - 1], d));
    rhs.push_back(Eigen::Vector3d::Zero());
    for (int s = 0; s + 1 < m; ++s) {
      rows.push_back(row(s, T[s], d) - row(s + 1, 0.0, d));
      rhs.push_back(Eigen::Vector3d::Zero());
    }
  }
  const int c = static_cast<int>(rows.size());
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(n + c, n + c);
  kkt.topLeftCorner(n, n) = 2.0 * q;
  for (int i = 0; i < c; ++i) {
    kkt.block(n + i, 0, 1, n) = rows[i];
    kkt.block(0, n + i, n, 1) = rows[i].transpose();
  }
  std::vector<Eigen::VectorXd> out;
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n + c);
    for (int i = 0; i < c; ++i) b(n + i) = rhs[i](axis);
    out.push_back(kkt.fullPivLu().solve(b).head(n));
  }
  return out;
}

TEST(Spline7, MatchesDenseKktReference) {
  for (unsigned seed = 200; seed < 206; ++seed) {
    // Durations of a few seconds keep the reference's local-time monomials well conditioned.
    const auto waypoints = testing::randomWalk(seed, 5, 20.0, 60.0);
    const auto durations = eq3Durations(waypoints, 20.0);
    auto segments = solveMinimumSnapSpline(waypoints, durations);
    ASSERT_TRUE(segments.ok());
    const auto reference = denseKktReference(waypoints, durations);
    for (std::size_t s = 0; s < durations.size(); ++s) {
      for (double f : {0.13, 0.5, 0.91}) {
        const double t = f * durations[s];
        for (int axis = 0; axis < 3; ++axis) {
          double x = 0.0;
          for (int k = 7; k >= 0; --k) x = x * t + reference[axis](8 * static_cast<int>(s) + k);
          EXPECT_NEAR((*segments)[s].evaluate(t, Derivative::kPosition)(axis), x, 1e-5) << "seed " << seed;
        }
      }
    }
  }
}

std::vector<KnotDerivatives> knotsOf(const std::vector<Segment>& segments) {
  std::vector<KnotDerivatives> k;
  for (const Segment& s : segments)
    k.push_back({s.evaluate(0, Derivative::kVelocity), s.evaluate(0, Derivative::kAcceleration),
                 s.evaluate(0, Derivative::kJerk)});
  const Segment& last = segments.back();
  k.push_back({last.evaluate(last.duration_s, Derivative::kVelocity),
               last.evaluate(last.duration_s, Derivative::kAcceleration),
               last.evaluate(last.duration_s, Derivative::kJerk)});
  return k;
}

TEST(Spline7, MinimumSnapBeatsNaiveAlternatives) {
  for (unsigned seed = 300; seed < 310; ++seed) {
    const auto w = testing::randomWalk(seed, 15);
    const auto durations = eq3Durations(w, 40.0);
    auto optimum = solveMinimumSnapSpline(w, durations);
    ASSERT_TRUE(optimum.ok());
    const double best = snapCost(*optimum);
    // Naive: Catmull-Rom velocities (chord through the neighbours), zero acceleration and jerk.
    std::vector<KnotDerivatives> naive(w.size());
    for (std::size_t i = 1; i + 1 < w.size(); ++i)
      naive[i].velocity_mps = (w[i + 1] - w[i - 1]) / (durations[i - 1] + durations[i]);
    auto naive_spline = hermiteSpline(w, durations, naive);
    ASSERT_TRUE(naive_spline.ok());
    EXPECT_LE(best, snapCost(*naive_spline));
    // Random perturbations of the optimum's interior derivatives never do better.
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 1.0);
    const auto knots = knotsOf(*optimum);
    for (int trial = 0; trial < 10; ++trial) {
      auto perturbed = knots;
      for (std::size_t i = 1; i + 1 < perturbed.size(); ++i) {
        const double scale = 0.01 * (trial + 1);
        perturbed[i].velocity_mps += scale * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
        perturbed[i].acceleration_mps2 += 0.1 * scale * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
        perturbed[i].jerk_mps3 += 0.01 * scale * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      }
      auto alternative = hermiteSpline(w, durations, perturbed);
      ASSERT_TRUE(alternative.ok());
      EXPECT_LE(best, snapCost(*alternative) * (1.0 + 1e-12)) << "seed " << seed << " trial " << trial;
    }
  }
}

TEST(Spline7, SnapCostMatchesQuadrature) {
  const auto w = testing::randomWalk(11, 6);
  auto segments = solveMinimumSnapSpline(w, eq3Durations(w, 30.0));
  ASSERT_TRUE(segments.ok());
  double integral = 0.0;
  for (const Segment& s : *segments) {
    const int n = 2000;  // midpoint rule
    for (int i = 0; i < n; ++i) {
      const double t = (i + 0.5) * s.duration_s / n;
      integral += s.evaluate(t, Derivative::kSnap).squaredNorm() * s.duration_s / n;
    }
  }
  EXPECT_NEAR(snapCost(*segments), integral, 1e-4 * integral);
}

TEST(Spline7, BadInputNamesTheField) {
  const std::vector<Eigen::Vector3d> one{{0, 0, 0}};
  auto r = solveMinimumSnapSpline(one, {});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "waypoints");
  std::vector<Eigen::Vector3d> nan{{0, 0, 0}, {1, std::nan(""), 0}, {2, 0, 0}};
  r = solveMinimumSnapSpline(nan, {1.0, 1.0});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "waypoints[1]");
  const std::vector<Eigen::Vector3d> three{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  r = solveMinimumSnapSpline(three, {1.0, 0.0});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "durations_s[1]");
  r = solveMinimumSnapSpline(three, {1.0});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "durations_s");
  SplineBoundary b;
  b.end.velocity_mps.x() = std::numeric_limits<double>::infinity();
  r = solveMinimumSnapSpline(three, {1.0, 1.0}, b);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().field, "boundary.end.velocity_mps");
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
}

}  // namespace
}  // namespace skyroute
