// Time to build a trajectory from 10, 50 and 200 waypoints: the minimum-snap spline solve alone,
// and the whole build (extra waypoints at 100 m, trapezoidal time allocation, spline, feasibility
// check at 0.05 s and repair, limits only), plus sampling at 0.1 s. Prints a table (median of
// repeated runs); docs/benchmarks/trajectory.md records the numbers.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <random>
#include <vector>

#include "trajectory/spline7.hpp"
#include "trajectory/time_allocation.hpp"
#include "trajectory/trajectory_builder.hpp"

namespace {

using skyroute::VehicleLimits;

// The same kind of path as the tests: legs of 50-400 m, turns up to 150 degrees, gentle slopes.
std::vector<Eigen::Vector3d> randomWalk(unsigned seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> leg(50.0, 400.0), turn(-150.0, 150.0), slope(-0.15, 0.15);
  std::vector<Eigen::Vector3d> points{{0.0, 0.0, 500.0}};
  double heading = 0.0;
  for (int i = 1; i < count; ++i) {
    heading += turn(rng) * std::numbers::pi / 180.0;
    const double l = leg(rng);
    points.push_back(points.back() + Eigen::Vector3d(l * std::sin(heading), l * std::cos(heading), l * slope(rng)));
  }
  return points;
}

struct Timing {
  double min_ms;
  double median_ms;
};

// The machine is shared (2 cores, other builds running): the minimum is the cost of the work, the
// median shows the noise.
template <class F>
Timing timeMs(int repeats, F&& f) {
  std::vector<double> ms;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    f();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(ms.begin(), ms.end());
  return {ms.front(), ms[ms.size() / 2]};
}

}  // namespace

int main() {
  std::printf("| waypoints | knots (100 m spacing) | spline solve ms min / median | full build ms min / median | "
              "repair rounds | status | flight s | sample at 0.1 s ms min / median |\n|---|---|---|---|---|---|---|---|\n");
  for (int count : {10, 50, 200}) {
    const auto waypoints = randomWalk(1234, count);
    const VehicleLimits limits;
    skyroute::TrajectoryOptions options;
    const auto knots = skyroute::densifyWaypoints(waypoints, options.waypoint_spacing_m).points;
    const auto durations = skyroute::allocateTimes(knots, limits).value();
    const int repeats = count >= 200 ? 15 : 41;
    const Timing solve_ms = timeMs(repeats, [&] {
      auto s = skyroute::solveMinimumSnapSpline(knots, durations);
      if (!s.ok()) std::abort();
    });
    skyroute::BuiltTrajectory last;
    const Timing build_ms = timeMs(repeats, [&] { last = skyroute::buildTrajectory(waypoints, limits, options).value(); });
    const Timing sample_ms = timeMs(repeats, [&] {
      auto samples = last.trajectory.sample(0.1);
      if (samples.empty()) std::abort();
    });
    std::printf("| %d | %zu | %.3f / %.3f | %.2f / %.2f | %d | %s | %.1f | %.3f / %.3f |\n", count, knots.size(),
                solve_ms.min_ms, solve_ms.median_ms, build_ms.min_ms, build_ms.median_ms, last.report.repair_rounds,
                std::string(skyroute::to_string(last.report.status)).c_str(), last.trajectory.duration_s(),
                sample_ms.min_ms, sample_ms.median_ms);
  }
  return 0;
}
