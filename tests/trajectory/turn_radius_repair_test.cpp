// Turn-radius repair by corner rounding: the fillet and pass-through geometry on its own; a zig-zag
// too sharp for a 50 m turn radius becomes feasible, with the radius measured independently from
// positions only; fixed waypoints are still flown through exactly; an obstacle inside a corner
// forces a smaller fillet or a clear failure; and with no turn limit nothing changes at all.
#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "tests/trajectory/finite_differences.hpp"
#include "tests/trajectory/random_paths.hpp"
#include "trajectory/corner_rounding.hpp"
#include "trajectory/trajectory_builder.hpp"

namespace skyroute {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// Smallest radius of curvature |v|^3 / |v x a| where the speed is at least min_speed_mps, with v and
// a from central differences of positions every 0.01 s (not the polynomials' derivatives).
double measureMinTurnRadius(const Trajectory& t, double min_speed_mps) {
  double best = std::numeric_limits<double>::infinity();
  testing::forEachFiniteDifference(t, [&](double, const Eigen::Vector3d& v, const Eigen::Vector3d& a) {
    if (v.norm() < min_speed_mps) return;
    const double cross = v.cross(a).norm();
    if (cross > 0.0) best = std::min(best, std::pow(v.norm(), 3) / cross);
  });
  return best;
}

double pathLength(const Trajectory& t) {
  double length = 0.0;
  Eigen::Vector3d previous = t.evaluate(0.0, Derivative::kPosition);
  for (double time = 0.01; time <= t.duration_s(); time += 0.01) {
    const Eigen::Vector3d p = t.evaluate(time, Derivative::kPosition);
    length += (p - previous).norm();
    previous = p;
  }
  return length;
}

double distanceToSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double u = std::clamp((p - a).dot(d) / std::max(d.squaredNorm(), 1e-12), 0.0, 1.0);
  return (a + u * d - p).norm();
}

// Five corners of 106 degrees each, climbing then descending (3D): the minimum-snap spline turns
// through them at under 10 m.
std::vector<Eigen::Vector3d> zigZag() {
  return {{0, 0, 500}, {300, 400, 520}, {600, 0, 540}, {900, 400, 560}, {1200, 0, 560}, {1500, 400, 540}};
}

VehicleLimits fixedWing() {
  VehicleLimits limits;
  limits.min_turn_radius_m = 50.0;
  return limits;
}

// Inward unit bisector of the corner at p (points to the arc's centre).
Eigen::Vector3d inwardBisector(const Eigen::Vector3d& a, const Eigen::Vector3d& p, const Eigen::Vector3d& b) {
  return ((b - p).normalized() - (p - a).normalized()).normalized();
}

TEST(CornerRounding, FilletIsTangentArcInTheLegsPlane) {
  // A 3D corner: the legs climb and turn.
  const Eigen::Vector3d a(0, 0, 100), p(400, 0, 160), b(450, 350, 120);
  const double radius = 60.0;
  auto corner = roundCorner(CornerMethod::kFillet, a, p, b, radius, 0.5, 0.5);
  ASSERT_TRUE(corner.has_value());
  const double phi = deflectionAngle(a, p, b);
  EXPECT_NEAR(corner->deflection_rad, phi, 1e-12);
  const double d = radius * std::tan(0.5 * phi);
  const auto& q = corner->points;
  ASSERT_GE(q.size(), 3u);
  EXPECT_LT((q.front() - (p - d * (p - a).normalized())).norm(), 1e-9);
  EXPECT_LT((q.back() - (p + d * (b - p).normalized())).norm(), 1e-9);
  // Every point is R from the centre and in the plane of the legs; consecutive points at most
  // arc_step apart in angle.
  const Eigen::Vector3d normal = (p - a).cross(b - p).normalized();
  const Eigen::Vector3d centre = p + inwardBisector(a, p, b) * radius / std::cos(0.5 * phi);
  for (std::size_t k = 0; k < q.size(); ++k) {
    EXPECT_NEAR((q[k] - centre).norm(), radius, 1e-9) << k;
    EXPECT_NEAR((q[k] - p).dot(normal), 0.0, 1e-9) << k;
    if (k > 0) {
      const double step =
          std::acos(std::clamp((q[k] - centre).normalized().dot((q[k - 1] - centre).normalized()), -1.0, 1.0));
      EXPECT_LE(step, CornerRoundingOptions{}.arc_step_deg * kDegToRad + 1e-9);
    }
  }
  EXPECT_EQ(corner->kept_point, static_cast<std::size_t>(-1));
  // Needs more than the share of a leg: no fillet; the largest fitting one is the closed form.
  EXPECT_FALSE(roundCorner(CornerMethod::kFillet, a, p, b, 1000.0, 0.5, 0.5).has_value());
  const double room = 0.5 * std::min((p - a).norm(), (b - p).norm());
  EXPECT_NEAR(largestFittingRadius(CornerMethod::kFillet, a, p, b, 1e6, 0.5, 0.5), room / std::tan(0.5 * phi), 1e-6);
  EXPECT_DOUBLE_EQ(largestFittingRadius(CornerMethod::kFillet, a, p, b, 30.0, 0.5, 0.5), 30.0);
  // A straight vertex has no corner; a reversal cannot be filleted.
  EXPECT_FALSE(roundCorner(CornerMethod::kFillet, a, p, p + (p - a), radius, 0.5, 0.5).has_value());
  EXPECT_FALSE(roundCorner(CornerMethod::kFillet, a, p, a, radius, 0.5, 0.5).has_value());
}

TEST(CornerRounding, PassThroughKeepsThePointOnTheBisector) {
  const Eigen::Vector3d a(0, 0, 100), p(500, 0, 100), b(200, 400, 100);  // about 127 degrees
  const double radius = 50.0;
  auto corner = roundCorner(CornerMethod::kPassThrough, a, p, b, radius, 0.5, 0.5);
  ASSERT_TRUE(corner.has_value());
  ASSERT_LT(corner->kept_point, corner->points.size());
  const auto& q = corner->points;
  EXPECT_EQ(q[corner->kept_point], p);  // exactly, not approximately
  // The neighbours of p are on the line through p along the bisector of the turn, one each side.
  const Eigen::Vector3d h = ((p - a).normalized() + (b - p).normalized()).normalized();
  const Eigen::Vector3d before = q[corner->kept_point - 1] - p;
  const Eigen::Vector3d after = q[corner->kept_point + 1] - p;
  EXPECT_LT(before.normalized().dot(h), -1.0 + 1e-9);
  EXPECT_GT(after.normalized().dot(h), 1.0 - 1e-9);
  // The path turns only at the arcs: no vertex turns by more than the arc step.
  std::vector<Eigen::Vector3d> chain{a};
  chain.insert(chain.end(), q.begin(), q.end());
  chain.push_back(b);
  for (std::size_t k = 1; k + 1 < chain.size(); ++k)
    EXPECT_LE(deflectionAngle(chain[k - 1], chain[k], chain[k + 1]),
              CornerRoundingOptions{}.arc_step_deg * kDegToRad + 1e-9);
  EXPECT_NEAR(deflectionAngle(chain[corner->kept_point], p, chain[corner->kept_point + 2]), 0.0, 1e-9);
  // A reversal can be flown through as well (a teardrop), but not filleted.
  auto reversal = roundCorner(CornerMethod::kPassThrough, a, p, Eigen::Vector3d(100, 0, 100), radius, 0.5, 0.5);
  ASSERT_TRUE(reversal.has_value());
  EXPECT_EQ(reversal->points[reversal->kept_point], p);
  // Too short legs for the radius.
  EXPECT_FALSE(roundCorner(CornerMethod::kPassThrough, a, p, b, 1000.0, 0.5, 0.5).has_value());
  const double largest = largestFittingRadius(CornerMethod::kPassThrough, a, p, b, 1000.0, 0.5, 0.5);
  EXPECT_GT(largest, radius);
  EXPECT_TRUE(roundCorner(CornerMethod::kPassThrough, a, p, b, largest, 0.5, 0.5).has_value());
  EXPECT_FALSE(roundCorner(CornerMethod::kPassThrough, a, p, b, largest * 1.01, 0.5, 0.5).has_value());
}

TEST(TurnRadiusRepair, ZigZagBecomesFeasible) {
  const auto w = zigZag();
  const VehicleLimits limits = fixedWing();
  // Without rounding it cannot be repaired: the corners are far too sharp.
  TrajectoryOptions off;
  off.round_corners = false;
  auto sharp = buildTrajectory(w, limits, off);
  ASSERT_TRUE(sharp.ok());
  EXPECT_EQ(sharp->report.status, TrajectoryStatus::kInfeasible);
  EXPECT_LT(measureMinTurnRadius(sharp->trajectory, limits.turn_check_min_speed_mps), 20.0);

  auto built = buildTrajectory(w, limits);
  ASSERT_TRUE(built.ok());
  const TrajectoryBuildReport& report = built->report;
  EXPECT_EQ(report.status, TrajectoryStatus::kRepaired) << report.failure_reason;
  EXPECT_TRUE(report.final_check.ok());
  EXPECT_EQ(report.corners_rounded, 4u);
  ASSERT_GE(report.repairs.size(), 4u);
  EXPECT_NE(report.repairs.front().find("fillet"), std::string::npos) << report.repairs.front();
  const double measured = measureMinTurnRadius(built->trajectory, limits.turn_check_min_speed_mps);
  EXPECT_GE(measured, limits.min_turn_radius_m);
  // Fillets cut the corners: shorter than the polyline.
  double polyline_m = 0.0;
  for (std::size_t i = 1; i < w.size(); ++i) polyline_m += (w[i] - w[i - 1]).norm();
  EXPECT_LT(pathLength(built->trajectory), polyline_m);
  // Ends unchanged; the cut corners are gone from the knots; the curve stays near the corners
  // (the fillet's middle is R (1 / cos(phi / 2) - 1) = 43 m inside a 65 m fillet's corner).
  EXPECT_LT((built->trajectory.evaluate(0.0, Derivative::kPosition) - w.front()).norm(), 1e-9);
  EXPECT_LT((built->trajectory.evaluate(built->trajectory.duration_s(), Derivative::kPosition) - w.back()).norm(),
            1e-9);
  for (std::size_t i = 1; i + 1 < w.size(); ++i)
    for (const Eigen::Vector3d& k : built->knots) EXPECT_GT((k - w[i]).norm(), 1.0) << i;
  for (double t = 0.0; t <= built->trajectory.duration_s(); t += 0.05) {
    const Eigen::Vector3d p = built->trajectory.evaluate(t, Derivative::kPosition);
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < w.size(); ++i) nearest = std::min(nearest, distanceToSegment(p, w[i], w[i + 1]));
    ASSERT_LT(nearest, 30.0) << t;
  }
}

TEST(TurnRadiusRepair, FixedWaypointsArePassedExactly) {
  const auto w = zigZag();
  const VehicleLimits limits = fixedWing();
  TrajectoryOptions options;
  options.fixed_waypoints = {3, 1, 3};  // any order, duplicates fine
  auto built = buildTrajectory(w, limits, options);
  ASSERT_TRUE(built.ok());
  EXPECT_EQ(built->report.status, TrajectoryStatus::kRepaired) << built->report.failure_reason;
  EXPECT_EQ(built->report.corners_rounded, 4u);
  EXPECT_GE(measureMinTurnRadius(built->trajectory, limits.turn_check_min_speed_mps), limits.min_turn_radius_m);
  const auto& knots = built->knots;
  const auto& times = built->trajectory.knotTimes();
  for (std::size_t i : {std::size_t{1}, std::size_t{3}}) {
    std::size_t k = 0;
    while (k < knots.size() && knots[k] != w[i]) ++k;  // bit-exact: the point itself is a knot
    ASSERT_LT(k, knots.size()) << "waypoint " << i;
    EXPECT_LT((built->trajectory.evaluate(times[k], Derivative::kPosition) - w[i]).norm(), 1e-6) << i;
    // Flown straight through along the bisector of the turn.
    const Eigen::Vector3d h = ((w[i] - w[i - 1]).normalized() + (w[i + 1] - w[i]).normalized()).normalized();
    const Eigen::Vector3d v = built->trajectory.evaluate(times[k], Derivative::kVelocity);
    EXPECT_GT(v.normalized().dot(h), std::cos(3.0 * kDegToRad)) << i;
    const Eigen::Vector3d a = built->trajectory.evaluate(times[k], Derivative::kAcceleration);
    EXPECT_LT(v.cross(a).norm() / std::pow(v.norm(), 3), 1.0 / limits.min_turn_radius_m) << i;
  }
  // The unfixed corners were cut.
  for (std::size_t i : {std::size_t{2}, std::size_t{4}})
    for (const Eigen::Vector3d& k : knots) EXPECT_GT((k - w[i]).norm(), 1.0) << i;
  // Out of range: an error naming the field.
  options.fixed_waypoints = {w.size()};
  auto bad = buildTrajectory(w, limits, options);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().field, "options.fixed_waypoints");
}

// A sphere of radius r at c, as a motion check that rejects every motion touching it.
MotionCheck sphereCheck(const Eigen::Vector3d& c, double r) {
  return [c, r](const Eigen::Vector3d& a, double, const Eigen::Vector3d& b, double) {
    return distanceToSegment(c, a, b) > r;
  };
}

TEST(TurnRadiusRepair, ObstacleInsideACornerGetsASmallerFilletOrAClearFailure) {
  const auto w = zigZag();
  const VehicleLimits limits = fixedWing();
  const Eigen::Vector3d into = inwardBisector(w[1], w[2], w[3]);
  const double phi = deflectionAngle(w[1], w[2], w[3]);
  auto middle_of_arc = [&](double radius) { return radius * (1.0 / std::cos(0.5 * phi) - 1.0); };
  // A small sphere just where the preferred 65 m fillet's arc passes (43 m in from the corner),
  // clear of the legs and of a 60 m fillet's arc (40 m in).
  const double preferred = CornerRoundingOptions{}.radius_factor * limits.min_turn_radius_m;
  const double at = middle_of_arc(preferred) - 0.5;
  const Eigen::Vector3d centre = w[2] + into * at;
  const double r = 1.5;
  ASSERT_GT(at - r, middle_of_arc(0.93 * preferred) + 0.6);
  MotionCheck near = sphereCheck(centre, r);
  auto built = buildTrajectory(w, limits, {}, &near);
  ASSERT_TRUE(built.ok());
  ASSERT_EQ(built->report.status, TrajectoryStatus::kRepaired) << built->report.failure_reason;
  bool smaller = false;
  for (const std::string& line : built->report.repairs)
    if (line.find("waypoint 2") != std::string::npos && line.find("collide") != std::string::npos) smaller = true;
  EXPECT_TRUE(smaller) << ::testing::PrintToString(built->report.repairs);
  EXPECT_GE(measureMinTurnRadius(built->trajectory, limits.turn_check_min_speed_mps), limits.min_turn_radius_m);
  for (double t = 0.0; t <= built->trajectory.duration_s(); t += 0.01)
    ASSERT_GT((built->trajectory.evaluate(t, Derivative::kPosition) - centre).norm(), r) << t;

  // A sphere across every arc from 65 m down to 50 m (but clear of the legs): a clear failure.
  const Eigen::Vector3d big_centre =
      w[2] + into * 0.5 * (middle_of_arc(limits.min_turn_radius_m) + middle_of_arc(preferred));
  const double big_r = 0.5 * (middle_of_arc(preferred) - middle_of_arc(limits.min_turn_radius_m)) + 3.0;
  ASSERT_GT(distanceToSegment(big_centre, w[1], w[2]), big_r);
  ASSERT_GT(distanceToSegment(big_centre, w[2], w[3]), big_r);
  MotionCheck blocked = sphereCheck(big_centre, big_r);
  auto failed = buildTrajectory(w, limits, {}, &blocked);
  ASSERT_TRUE(failed.ok());
  EXPECT_EQ(failed->report.status, TrajectoryStatus::kInfeasible);
  const std::string& why = failed->report.failure_reason;
  EXPECT_NE(why.find("waypoint 2"), std::string::npos) << why;
  EXPECT_NE(why.find("collides"), std::string::npos) << why;
}

TEST(TurnRadiusRepair, ReportsACornerWithTooLittleRoom) {
  // A 160 degree turn on 120 m legs: a 50 m fillet needs 284 m of each leg.
  const std::vector<Eigen::Vector3d> w{
      {0, 0, 500}, {120, 0, 500}, {120 - 120 * std::cos(20 * kDegToRad), 120 * std::sin(20 * kDegToRad), 500}};
  auto built = buildTrajectory(w, fixedWing());
  ASSERT_TRUE(built.ok());
  EXPECT_EQ(built->report.status, TrajectoryStatus::kInfeasible);
  EXPECT_NE(built->report.failure_reason.find("cannot be rounded"), std::string::npos) << built->report.failure_reason;
  EXPECT_NE(built->report.failure_reason.find("waypoint 1"), std::string::npos) << built->report.failure_reason;
}

TEST(TurnRadiusRepair, RandomPathsAreRepairedOrExplained) {
  // The kind of path LOSPO hands over, with a 50 m turn radius: every result within the limit by
  // the independent measure, or infeasible with a reason that names a corner. Measured from 2 m/s:
  // just above the 1 m/s check speed, leaving rest, the curvature changes within one 0.1 s step
  // of the builder's check (a limit of the check grid, not of the rounding).
  const VehicleLimits limits = fixedWing();
  int repaired = 0;
  for (unsigned seed = 1; seed <= 12; ++seed) {
    const auto w = testing::randomWalk(seed, 10, 150.0, 600.0, 120.0);
    auto built = buildTrajectory(w, limits);
    ASSERT_TRUE(built.ok());
    if (built->report.status == TrajectoryStatus::kInfeasible) {
      EXPECT_NE(built->report.failure_reason.find("waypoint"), std::string::npos) << built->report.failure_reason;
      continue;
    }
    if (built->report.status == TrajectoryStatus::kRepaired) ++repaired;
    EXPECT_GE(measureMinTurnRadius(built->trajectory, 2.0), limits.min_turn_radius_m) << seed;
  }
  EXPECT_GE(repaired, 8);
}

TEST(TurnRadiusRepair, NothingChangesWithoutATurnLimit) {
  const auto w = zigZag();
  VehicleLimits limits;
  limits.min_turn_radius_m = 0.0;
  auto plain = buildTrajectory(w, limits);
  TrajectoryOptions options;
  options.fixed_waypoints = {1, 2, 3, 4};
  options.corner_rounding.radius_factor = 1.5;
  auto with_options = buildTrajectory(w, limits, options);
  ASSERT_TRUE(plain.ok());
  ASSERT_TRUE(with_options.ok());
  auto same = [](const BuiltTrajectory& x, const BuiltTrajectory& y) {
    const auto& a = x.trajectory.segments();
    const auto& b = y.trajectory.segments();
    if (a.size() != b.size() || x.knots != y.knots) return false;
    for (std::size_t s = 0; s < a.size(); ++s) {
      if (a[s].duration_s != b[s].duration_s) return false;
      for (int axis = 0; axis < 3; ++axis)
        if (a[s].axes[static_cast<std::size_t>(axis)].coefficients() !=
            b[s].axes[static_cast<std::size_t>(axis)].coefficients())
          return false;
    }
    return true;
  };
  EXPECT_TRUE(same(*plain, *with_options));
  EXPECT_EQ(with_options->report.corners_rounded, 0u);
  // A turn limit the curve already keeps changes nothing either.
  const std::vector<Eigen::Vector3d> gentle{{0, 0, 500}, {1000, 0, 500}, {2000, 200, 500}};
  auto unlimited = buildTrajectory(gentle, limits);
  limits.min_turn_radius_m = 50.0;
  options.fixed_waypoints = {1};
  auto limited = buildTrajectory(gentle, limits, options);
  ASSERT_TRUE(unlimited.ok());
  ASSERT_TRUE(limited.ok());
  EXPECT_EQ(limited->report.status, TrajectoryStatus::kFeasible);
  EXPECT_TRUE(same(*unlimited, *limited));
}

}  // namespace
}  // namespace skyroute
