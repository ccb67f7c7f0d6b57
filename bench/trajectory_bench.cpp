// Time to build a trajectory from 10, 50 and 200 waypoints: the minimum-snap spline solve alone,
// and the whole build (extra waypoints at 100 m, trapezoidal time allocation, spline, feasibility
// check at 0.05 s and repair, limits only), plus sampling at 0.1 s. Prints a table (median of
// repeated runs); docs/benchmarks/trajectory.md records the numbers.
//
//   trajectory_bench                                      the build-time table
//   trajectory_bench --seed003 [--runs N] [--first-seed S] [--step-m M]
//
// --seed003: the experiments of seed 003 sections 2 and 3-1 on the replanning scenario's 12.6 km
// square of N44W072 (seed003Table1Scenario's start and goal, terrain only): RRT* stopped at 100
// and at 500 tree nodes (Figs 2-3), LOSPO on each path (Fig. 5, the 16.35 % reduction), and the
// 7th-order trajectory of the LOSPO path with eq. 3's constant V_ref, with and without the extra
// waypoints, and with our trapezoidal allocation (Figs 6-8: how far the curve strays from the path). One RRT* seed per run; --step-m:
// the RRT* steering range (default 20 % of the sampling box's diagonal, about 3.6 km here);
// docs/papers.md records the output.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "bench/seed003_world.hpp"
#include "planning/sampling/lospo.hpp"
#include "planning/sampling/rrt_star.hpp"
#include "planning/sampling/world_motion_validator.hpp"
#include "service/moving_obstacle_scenario.hpp"
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

double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

double distanceToPolyline(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& path) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Eigen::Vector3d d = path[i] - path[i - 1];
    const double t = std::clamp((p - path[i - 1]).dot(d) / std::max(d.squaredNorm(), 1e-12), 0.0, 1.0);
    best = std::min(best, (path[i - 1] + t * d - p).norm());
  }
  return best;
}

struct Summary {
  double mean, min, median, max;
};
Summary summarise(std::vector<double> v) {
  if (v.empty()) return {NAN, NAN, NAN, NAN};
  std::sort(v.begin(), v.end());
  double sum = 0.0;
  for (double x : v) sum += x;
  return {sum / static_cast<double>(v.size()), v.front(), v[v.size() / 2], v.back()};
}

// One seed: RRT* (plain: uniform sampling, no shortcut to the straight line) stopped at `nodes`
// tree nodes, then LOSPO with the product's options (LospoOptions{}).
struct NodeRun {
  bool solved = false;
  double rrt_m = 0.0, lospo_m = 0.0, rrt_cpu_ms = 0.0, lospo_cpu_ms = 0.0;
  std::uint64_t iterations = 0;
  std::vector<Eigen::Vector3d> lospo_path;
};
NodeRun runNodes(const skyroute::WorldMotionValidator& validator, const skyroute::MovingObstacleScenario& scenario,
                 std::uint64_t seed, std::uint64_t nodes, double step_m) {
  skyroute::RrtStarOptions options;
  options.seed = seed;
  options.informed_sampling = false;
  options.try_direct_first = false;
  options.max_nodes = nodes;
  options.max_step_m = step_m;
  NodeRun run;
  double c0 = threadCpuMs();
  auto rrt = skyroute::RrtStar(validator, options)
                 .plan(scenario.start_m, scenario.goal_m, skyroute::TerminationCondition().withIterationBudget(1000000));
  run.rrt_cpu_ms = threadCpuMs() - c0;
  if (!rrt.ok() || !rrt->solved()) return run;
  run.iterations = rrt->iterations;
  c0 = threadCpuMs();
  auto shortened = skyroute::lospo(validator, rrt->path_m, skyroute::LospoOptions{});
  run.lospo_cpu_ms = threadCpuMs() - c0;
  if (!shortened.ok()) return run;
  run.solved = true;
  run.rrt_m = rrt->length_m;
  run.lospo_m = shortened->length_m;
  run.lospo_path = shortened->path_m;
  return run;
}

// Figs 6-8: the LOSPO path as waypoints with eq. 3's constant V_ref (with and without the extra
// waypoints of Fig. 7) or our trapezoidal timing; how far the curve strays from the path (sampled
// every 0.1 s) and how long the flight is.
struct Fig8 {
  std::vector<double> max_dev_m, mean_dev_m, flight_s;
  int feasible = 0, built = 0;
};
void addFig8(Fig8& fig, const std::vector<Eigen::Vector3d>& path, skyroute::TimeAllocationMethod method,
             bool extra_waypoints) {
  skyroute::TrajectoryOptions options;
  options.time_allocation.method = method;
  if (!extra_waypoints) options.waypoint_spacing_m = 0.0;
  auto built = skyroute::buildTrajectory(path, skyroute::seed003ScenarioLimits(), options);
  if (!built.ok()) return;
  ++fig.built;
  fig.feasible += built->report.status != skyroute::TrajectoryStatus::kInfeasible ? 1 : 0;
  double worst = 0.0, sum = 0.0;
  const auto samples = built->trajectory.sample(0.1);
  for (const auto& state : samples) {
    const double d = distanceToPolyline(state.position_m, path);
    worst = std::max(worst, d);
    sum += d;
  }
  fig.max_dev_m.push_back(worst);
  fig.mean_dev_m.push_back(sum / static_cast<double>(std::max<std::size_t>(1, samples.size())));
  fig.flight_s.push_back(built->trajectory.duration_s());
}

// A table cell: the value, or "unsolved".
std::string cell(bool ok, double v, const char* fmt) {
  if (!ok) return "unsolved";
  char buf[32];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

struct NodeStats {
  int solved = 0;
  std::vector<double> length_m, lospo_m, lospo_cut_pct, iterations, rrt_ms, lospo_ms;
  void add(const NodeRun& run) {
    if (!run.solved) return;
    ++solved;
    length_m.push_back(run.rrt_m);
    lospo_m.push_back(run.lospo_m);
    lospo_cut_pct.push_back(100.0 * (1.0 - run.lospo_m / run.rrt_m));
    iterations.push_back(static_cast<double>(run.iterations));
    rrt_ms.push_back(run.rrt_cpu_ms);
    lospo_ms.push_back(run.lospo_cpu_ms);
  }
};

constexpr int kFig8Rows = 3;
const char* const kFig8Names[kFig8Rows] = {"constant V_ref (eq. 3), no extra waypoints (Fig. 6)",
                                           "constant V_ref (eq. 3), extra waypoints (Figs 7-8)",
                                           "trapezoidal (ours), extra waypoints"};

void printSeed003Summary(const NodeStats (&stats)[2], int runs, const std::vector<double>& change_500_pct,
                         const Fig8 (&fig8)[kFig8Rows]) {
  std::printf("\n| nodes | solved | RRT* m mean / median | iterations mean | RRT* CPU ms mean | LOSPO m mean | "
              "LOSPO cut %% mean / min / median / max | LOSPO CPU ms mean |\n|---|---|---|---|---|---|---|---|\n");
  for (int k = 0; k < 2; ++k) {
    const Summary l = summarise(stats[k].length_m), cut = summarise(stats[k].lospo_cut_pct);
    std::printf("| %d | %d/%d | %.0f / %.0f | %.0f | %.1f | %.0f | %.2f / %.2f / %.2f / %.2f | %.2f |\n", k == 0 ? 100 : 500,
                stats[k].solved, runs, l.mean, l.median, summarise(stats[k].iterations).mean, summarise(stats[k].rrt_ms).mean,
                summarise(stats[k].lospo_m).mean, cut.mean, cut.min, cut.median, cut.max, summarise(stats[k].lospo_ms).mean);
  }
  const Summary d500 = summarise(change_500_pct);
  std::printf("\n500 nodes against 100 (same seed, both solved, %zu seeds): %+.2f %% mean, %+.2f %% median, %+.2f .. %+.2f %%\n",
              change_500_pct.size(), d500.mean, d500.median, d500.min, d500.max);
  std::printf("\n| Figs 6-8: trajectory of LOSPO(100) | built | feasible | max distance to path m median / max | "
              "mean distance m median | flight s median |\n|---|---|---|---|---|---|\n");
  for (int k = 0; k < kFig8Rows; ++k) {
    std::printf("| %s | %d | %d | %.1f / %.1f | %.2f | %.1f |\n", kFig8Names[k],
                fig8[k].built, fig8[k].feasible, summarise(fig8[k].max_dev_m).median, summarise(fig8[k].max_dev_m).max,
                summarise(fig8[k].mean_dev_m).median, summarise(fig8[k].flight_s).median);
  }
}

int seed003Figures(int runs, std::uint64_t first_seed, double step_m) {
  using namespace skyroute;
  auto world = bench::loadSeed003World();  // as the replanning benchmark flies the scenario
  if (!world) return 1;
  const MovingObstacleScenario scenario = seed003Table1Scenario(*world->heightfield);
  const double inf = std::numeric_limits<double>::infinity();
  const Eigen::Vector2d lo = scenario.corner_en_m, hi = lo + Eigen::Vector2d(12600.0, 12600.0);
  const WorldMotionValidator validator(
      world->collision, Eigen::AlignedBox3d(Eigen::Vector3d(lo.x(), lo.y(), -inf), Eigen::Vector3d(hi.x(), hi.y(), inf)));
  std::printf("## Seed 003 Figs 2, 3, 5, 8 on N44W072 (12.6 km square at 44.2 N, 71.9 W), %d RRT* seeds from %llu, "
              "steering range %s\n\n",
              runs, static_cast<unsigned long long>(first_seed),
              step_m > 0.0 ? (std::to_string(static_cast<int>(step_m)) + " m").c_str() : "20 % of the box diagonal");
  std::printf("start (%.0f, %.0f, %.0f) m, goal (%.0f, %.0f, %.0f) m ENU, straight line %.1f m, valid: %s\n\n",
              scenario.start_m.x(), scenario.start_m.y(), scenario.start_m.z(), scenario.goal_m.x(), scenario.goal_m.y(),
              scenario.goal_m.z(), (scenario.goal_m - scenario.start_m).norm(),
              validator.isMotionValid(scenario.start_m, scenario.goal_m) ? "yes" : "no");
  NodeStats stats[2];
  std::vector<double> change_500_pct;
  Fig8 fig8[kFig8Rows];
  std::printf("| seed | RRT* 100 nodes m | RRT* 500 nodes m | 500 vs 100 | LOSPO(100) m | LOSPO(100) vs RRT*(100) | "
              "LOSPO(500) vs RRT*(500) |\n|---|---:|---:|---:|---:|---:|---:|\n");
  for (int r = 0; r < runs; ++r) {
    const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(r);
    const NodeRun run[2] = {runNodes(validator, scenario, seed, 100, step_m), runNodes(validator, scenario, seed, 500, step_m)};
    stats[0].add(run[0]);
    stats[1].add(run[1]);
    if (run[0].solved) {
      addFig8(fig8[0], run[0].lospo_path, TimeAllocationMethod::kConstantSpeed, false);
      addFig8(fig8[1], run[0].lospo_path, TimeAllocationMethod::kConstantSpeed, true);
      addFig8(fig8[2], run[0].lospo_path, TimeAllocationMethod::kTrapezoidal, true);
    }
    const bool both = run[0].solved && run[1].solved;
    const double change = both ? 100.0 * (run[1].rrt_m / run[0].rrt_m - 1.0) : 0.0;
    if (both) change_500_pct.push_back(change);
    std::printf("| %llu | %s | %s | %s | %s | %s | %s |\n", static_cast<unsigned long long>(seed),
                cell(run[0].solved, run[0].rrt_m, "%.0f").c_str(), cell(run[1].solved, run[1].rrt_m, "%.0f").c_str(),
                cell(both, change, "%+.2f %%").c_str(), cell(run[0].solved, run[0].lospo_m, "%.0f").c_str(),
                cell(run[0].solved, 100.0 * (run[0].lospo_m / run[0].rrt_m - 1.0), "%+.2f %%").c_str(),
                cell(run[1].solved, 100.0 * (run[1].lospo_m / run[1].rrt_m - 1.0), "%+.2f %%").c_str());
    std::fflush(stdout);
  }
  printSeed003Summary(stats, runs, change_500_pct, fig8);
  return 0;
}

int buildTimeTable() {
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

}  // namespace

int main(int argc, char** argv) {
  bool seed003 = false;
  int runs = 20;
  std::uint64_t first_seed = 1;
  double step_m = 0.0;  // RrtStarOptions::max_step_m; 0 = its default
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seed003") seed003 = true;
    else if (a == "--runs" && i + 1 < argc) runs = std::atoi(argv[++i]);
    else if (a == "--first-seed" && i + 1 < argc) first_seed = std::strtoull(argv[++i], nullptr, 10);
    else if (a == "--step-m" && i + 1 < argc) step_m = std::atof(argv[++i]);
    else {
      std::fprintf(stderr, "usage: trajectory_bench [--seed003 [--runs N] [--first-seed S] [--step-m M]]\n");
      return 2;
    }
  }
  return seed003 ? seed003Figures(runs, first_seed, step_m) : buildTimeTable();
}
