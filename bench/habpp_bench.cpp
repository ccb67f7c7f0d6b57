// HAB-PP vs Improved HAB-PP (seed 004, section 5) next to 8-connected A* and Theta*, on Moving AI
// maps: 8room_000 cropped to 100x100 and 160x170 (stand-ins for the paper's office and apartment
// maps, which are not public) and Boston_0_256. Seeded runs per map (30 by default); prints one
// table per map with mean, median and max of first-path time, total time, length and angle change,
// then the box-plot statistics of both times (quartiles, Tukey's fence, outliers) that the seed's
// outlier evidence (Fig. 6) rests on.
// Times are processor time (std::clock) of this single-threaded process, so other work on a shared
// machine does not inflate them; the termination budget is wall time.
//
// Also RRT* with LOSPO (planning/sampling/rrt_star + planning/sampling/lospo through GridMotionValidator).
//
//   habpp_bench [--runs N] [--map office|apartment|boston]... [--budget-s S] [--stable N]
//               [--rrt-iterations N] [--no-hab] [--weights wL,wA,wP]
//               [--near-k 0|1] [--output-routes N] [--stop-top 0|1] [--draws N] [--published]
//               [--shared-tree 0|1] [--sample-eta 0|1] [--rest 0|1] [--node-redraws N] [--tree-route 0|1] [--after-solution N] [--corridor N] [--only 0|1] [--dump DIR]
//               [--tau-min X] [--window-segments N] [--window N] [--window-margin N]
// --budget-s: wall budget per HAB-PP run (default 120); --stable: stable_iterations override;
// --rrt-iterations: RRT* budget (0 skips that row); --no-hab: only the reference rows;
// --weights: eq. (2) weights instead of the paper's 1/3 each; --near-k: the RRT* species' k-nearest
// near set on (1) or off (0); --output-routes: top ranked routes the output stage may use;
// --stop-top: the RRT*-only change rule of the stopping rule on (1) or off (0); --draws: draws of
// x_rand per RRT* step; --published: the Improved row runs section 4 as published
// (HabPpParameters::improvedAsPublished: five trees from the start, no joining, no resting);
// --shared-tree, --sample-eta, --rest, --node-redraws, --tree-route, --after-solution, --corridor: the HabPpParameters of those names;
// --only 0|1: run HAB-PP (0) or Improved HAB-PP (1) alone, for profiling; --dump DIR: write every
// path found (and Theta*'s, A*'s) to DIR as "x y" lines, for plotting; --tau-min: pheromone_min;
// --window-segments, --window, --window-margin: output_window_segments, output_window_cells,
// output_window_margin_cells (the output stage's windowed re-planning).
//
// Writes nothing; docs/benchmarks/habpp.md records its output.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "bench/support/grid_motion_validator.hpp"
#include "planning/colony/hab_pp.hpp"
#include "planning/grid/any_angle_search.hpp"
#include "planning/grid/grid_search.hpp"
#include "planning/sampling/lospo.hpp"
#include "planning/sampling/rrt_star.hpp"
#include "terrain/movingai.hpp"

namespace {

using namespace skyroute;

struct Case {
  std::string name;
  std::string file;
  int x0, y0, width, height;  // crop; width 0 = whole map
  GridCell start, goal;       // in the cropped map's coordinates
  std::uint64_t rrt_iterations;  // RRT* + LOSPO budget: a few times what its first path needs here
};


// The cell nearest to c (Euclidean, then row-major) among those `ok` accepts.
template <class Ok>
GridCell nearestWhere(const GridLayer& g, GridCell c, Ok ok) {
  GridCell best = c;
  double best_d = 1e300;
  for (int y = 0; y < g.height(); ++y) {
    for (int x = 0; x < g.width(); ++x) {
      const double d = std::hypot(double(x - c.x), double(y - c.y));
      if (d < best_d && ok(GridCell{x, y})) {
        best_d = d;
        best = GridCell{x, y};
      }
    }
  }
  return best;
}

struct Stats {
  std::vector<double> first_s, total_s, length, angle;
  int solved = 0, converged = 0;
};

double mean(const std::vector<double>& v) {
  return v.empty() ? NAN : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}
double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}
// Linear interpolation between order statistics (q in [0, 1]).
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(pos);
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}
double maxOf(const std::vector<double>& v) { return v.empty() ? NAN : *std::max_element(v.begin(), v.end()); }
double minOf(const std::vector<double>& v) { return v.empty() ? NAN : *std::min_element(v.begin(), v.end()); }

void printRow(const char* name, const Stats& s, int runs);

// What the seed's box plots (Fig. 6) show of one sample: quartiles, the upper whisker's fence
// (Q3 + 1.5 IQR), the runs beyond it (outliers), and the runs beyond a common threshold (the
// other planner's fence), so the two planners' slow tails are counted against the same line.
void printBox(const char* planner, const char* what, const std::vector<double>& v, double common_fence) {
  const double q1 = quantile(v, 0.25), q3 = quantile(v, 0.75), fence = q3 + 1.5 * (q3 - q1);
  const auto beyond = [&](double line) { return std::count_if(v.begin(), v.end(), [&](double x) { return x > line; }); };
  std::printf("| %-16s | %-10s | %8.4f / %8.4f / %8.4f | %8.4f | %8.4f | %2td | %2td |\n", planner, what, q1,
              quantile(v, 0.5), q3, maxOf(v), fence, beyond(fence), beyond(common_fence));
}

// One "x y" line per point, for plotting runs (--dump).
void dumpPath(const std::string& file, const std::vector<GridCell>& path) {
  if (std::FILE* f = std::fopen(file.c_str(), "w")) {
    for (const GridCell& q : path) std::fprintf(f, "%d %d\n", q.x, q.y);
    std::fclose(f);
  }
}
double cpuSince(std::clock_t c0) { return static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC; }

// Sum of turning angles of a polyline (x, y only).
double angleChange(const std::vector<Eigen::Vector3d>& p) {
  double sum = 0.0;
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    const Eigen::Vector2d u = (p[i] - p[i - 1]).head<2>(), v = (p[i + 1] - p[i]).head<2>();
    if (u.norm() > 0.0 && v.norm() > 0.0) sum += std::acos(std::clamp(u.dot(v) / (u.norm() * v.norm()), -1.0, 1.0));
  }
  return sum;
}

// RRT* (planning/sampling/rrt_star, default options, seeded) on the grid through GridMotionValidator, its
// path flattened to z = 0 and shortened by LOSPO (1-cell spacing, up to 4 passes). An iteration
// budget, not a deadline, stops it, so a seed repeats exactly; the first-path time is the processor
// time of a second run of the same seed stopped at the iteration that found the first path (the
// same tree, bit for bit). "Total" = the full RRT* run plus LOSPO.
void rrtStarLospoRow(const GridLayer& grid, GridCell start, GridCell goal, int runs, std::uint64_t iterations) {
  const GridMotionValidator validator(grid);
  Stats s;
  double mean_first_iteration = 0.0;
  for (int r = 0; r < runs; ++r) {
    RrtStarOptions o;
    o.seed = 1000 + static_cast<std::uint64_t>(r);
    const RrtStar planner(validator, o);
    const Eigen::Vector3d from(start.x, start.y, 0.0), to(goal.x, goal.y, 0.0);
    const std::clock_t c0 = std::clock();
    auto plan = planner.plan(from, to, TerminationCondition().withIterationBudget(iterations));
    if (!plan.ok() || !plan->solved()) continue;
    std::vector<Eigen::Vector3d> path = plan->path_m;
    for (Eigen::Vector3d& q : path) q.z() = 0.0;
    auto shortened = lospo(validator, path, LospoOptions{.spacing_m = 1.0, .max_passes = 4});
    const double total_s = cpuSince(c0);
    if (!shortened.ok()) continue;
    const std::clock_t c1 = std::clock();
    auto first = planner.plan(from, to, TerminationCondition().withIterationBudget(plan->first_solution_iteration));
    const double first_s = cpuSince(c1);
    ++s.solved;
    ++s.converged;
    s.first_s.push_back(first.ok() && first->solved() ? first_s : NAN);
    s.total_s.push_back(total_s);
    s.length.push_back(shortened->length_m);
    s.angle.push_back(angleChange(shortened->path_m));
    mean_first_iteration += static_cast<double>(plan->first_solution_iteration) / runs;
  }
  printRow("RRT* + LOSPO", s, runs);
  std::printf("|   (details) | RRT* budget %llu iterations; mean iterations to the first path %.0f |\n",
              static_cast<unsigned long long>(iterations), mean_first_iteration);
}

void printRow(const char* name, const Stats& s, int runs) {
  std::printf("| %-16s | %2d/%2d | %2d | %8.4f / %8.4f / %8.4f | %8.4f / %8.4f / %8.4f | %8.2f / %8.2f / %8.2f | %6.3f |\n",
              name, s.solved, runs, s.converged, mean(s.first_s), median(s.first_s), maxOf(s.first_s), mean(s.total_s),
              median(s.total_s), maxOf(s.total_s), mean(s.length), minOf(s.length), maxOf(s.length), mean(s.angle));
  std::fflush(stdout);
}

// The seed's evidence that Improved HAB-PP leaves local minima sooner: fewer runs at the top of
// the total-time box plot. The common line is HAB-PP's own fence.
void printBoxPlots(const Stats& hab, const Stats& improved) {
  std::printf("\n| planner          | time       | Q1 / median / Q3 s | max s | fence s | outliers | beyond HAB-PP's fence |\n"
              "|---|---|---|---|---|---|---|\n");
  for (const bool first_path : {true, false}) {
    const char* what = first_path ? "first path" : "total";
    const std::vector<double>& base = first_path ? hab.first_s : hab.total_s;
    const double common = quantile(base, 0.75) + 1.5 * (quantile(base, 0.75) - quantile(base, 0.25));
    printBox("HAB-PP", what, base, common);
    printBox("Improved HAB-PP", what, first_path ? improved.first_s : improved.total_s, common);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 30;
  double budget_s = 120.0;
  int stable = 0;  // 0: the default HabPpParameters::stable_iterations
  long long rrt_iterations = -1;  // RRT* + LOSPO iteration budget; -1: the map's; 0 skips the row
  bool hab = true;
  int near_k = -1;          // --near-k 0|1: HabPpParameters::rrt_near_nearest; -1: the default
  int output_routes = -1;   // --output-routes N: HabPpParameters::output_ranked_routes; -1: the default
  int stop_top = -1;        // --stop-top 0|1: HabPpParameters::rrt_stop_top_paths; -1: the default
  int draws = -1;           // --draws N: HabPpParameters::rrt_draws_per_step; -1: the default
  int shared_tree = -1;     // --shared-tree 0|1: HabPpParameters::rrt_shared_tree; -1: the default
  bool published = false;   // --published: Improved HAB-PP as section 4 publishes it (improvedAsPublished)
  int node_redraws = -1, tree_route = -1;
  int rest = -1;            // --rest 0|1: HabPpParameters::rrt_rest_when_full
  int after_solution = -1;  // --after-solution N: HabPpParameters::rrt_nodes_after_solution
  int corridor = -2;        // --corridor N: HabPpParameters::output_corridor_cells
  int only = -1;            // --only 0|1: run HAB-PP (0) or Improved HAB-PP (1) alone (profiling)
  int sample_eta = -1;      // --sample-eta 0|1: HabPpParameters::rrt_sample_visibility; -1: the default
  double window = -1.0;      // --window N: HabPpParameters::output_window_cells
  int window_segments = -1; // --window-segments N: HabPpParameters::output_window_segments
  int window_margin = -1;   // --window-margin N: HabPpParameters::output_window_margin_cells
  double tau_min = -1.0;    // --tau-min X: HabPpParameters::pheromone_min
  std::string dump_dir;     // --dump DIR: each HAB-PP path as DIR/<map>_<planner>_<seed>.txt ("x y" per line)
  double weights[3] = {-1.0, -1.0, -1.0};  // w_L, w_A, w_P of eq. (2); negative: the paper's 1/3 each
  std::vector<std::string> wanted;
  // The options that take one integer.
  const std::pair<const char*, int*> int_options[] = {
      {"--runs", &runs}, {"--stable", &stable}, {"--near-k", &near_k}, {"--output-routes", &output_routes},
      {"--stop-top", &stop_top}, {"--draws", &draws}, {"--shared-tree", &shared_tree}, {"--sample-eta", &sample_eta},
      {"--rest", &rest}, {"--node-redraws", &node_redraws}, {"--tree-route", &tree_route}, {"--corridor", &corridor},
      {"--after-solution", &after_solution}, {"--only", &only}, {"--window-segments", &window_segments},
      {"--window-margin", &window_margin}};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    int* int_option = nullptr;
    for (const auto& [name, target] : int_options)
      if (a == name) int_option = target;
    if (int_option != nullptr && i + 1 < argc) *int_option = std::atoi(argv[++i]);
    else if (a == "--map" && i + 1 < argc) wanted.push_back(argv[++i]);
    else if (a == "--budget-s" && i + 1 < argc) budget_s = std::atof(argv[++i]);
    else if (a == "--rrt-iterations" && i + 1 < argc) rrt_iterations = std::atoll(argv[++i]);
    else if (a == "--no-hab") hab = false;
    else if (a == "--published") published = true;
    else if (a == "--dump" && i + 1 < argc) dump_dir = argv[++i];
    else if (a == "--window" && i + 1 < argc) window = std::atof(argv[++i]);
    else if (a == "--tau-min" && i + 1 < argc) tau_min = std::atof(argv[++i]);
    else if (a == "--weights" && i + 1 < argc) {
      if (std::sscanf(argv[++i], "%lf,%lf,%lf", &weights[0], &weights[1], &weights[2]) != 3) return 2;
    }
    else {
      std::fprintf(stderr, "usage: habpp_bench [--runs N] [--map office|apartment|boston]... [--budget-s S] [--stable N] [--rrt-iterations N] [--no-hab] [--weights wL,wA,wP] [--near-k 0|1] [--output-routes N] [--stop-top 0|1] [--draws N] [--published] [--shared-tree 0|1] [--sample-eta 0|1] [--rest 0|1] [--node-redraws N] [--tree-route 0|1] [--after-solution N] [--corridor N] [--only 0|1] [--dump DIR] [--tau-min X] [--window-segments N] [--window N] [--window-margin N]\n");
      return 2;
    }
  }
  const std::string dir = std::string(SKYROUTE_SHARED_DATA_DIR) + "/movingai/";
  std::vector<Case> cases = {
      {"office", "8room_000.map", 0, 0, 100, 100, {}, {}, 200000},
      {"apartment", "8room_000.map", 0, 0, 160, 170, {}, {}, 400000},
      {"boston", "Boston_0_256.map", 0, 0, 0, 0, GridCell{5, 14}, GridCell{254, 254}, 50000},
  };
  for (Case& c : cases) {
    if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), c.name) == wanted.end()) continue;
    auto full = loadMovingAiMap(dir + c.file);
    if (!full) {
      std::fprintf(stderr, "%s\n", full.error().describe().c_str());
      return 1;
    }
    const GridLayer grid = c.width > 0 ? full->cropped(GridCell{c.x0, c.y0}, c.width, c.height) : *full;
    if (c.width > 0) {  // corners of the crop
      c.start = nearestWhere(grid, GridCell{0, 0}, [&](GridCell q) { return grid.passable(q); });
      // The goal: the cell nearest the opposite corner that the start can reach.
      const std::vector<std::uint8_t> reach = reachableCells(grid, c.start);
      c.goal = nearestWhere(grid, GridCell{grid.width() - 1, grid.height() - 1},
                            [&](GridCell q) { return reach[grid.index(q)] != 0; });
    }
    std::printf("\n### %s: %s %dx%d (crop at %d,%d), start (%d,%d), goal (%d,%d), %d runs\n\n", c.name.c_str(),
                c.file.c_str(), grid.width(), grid.height(), c.x0, c.y0, c.start.x, c.start.y, c.goal.x, c.goal.y, runs);
    std::printf("| planner          | found | conv | first path s mean/median/max | total s mean/median/max "
                "| length mean/min/max | angle rad |\n|---|---|---|---|---|---|---|\n");
    Stats astar, theta;
    for (int r = 0; r < runs; ++r) {
      for (auto [fn, st] : {std::pair{&gridAStar8, &astar}, std::pair{&thetaStar, &theta}}) {
        const std::clock_t c0 = std::clock();
        const AnyAngleResult res = fn(grid, c.start, c.goal, TerminationCondition{});
        const double cpu_s = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
        if (res.status != PlannerStatus::kSolved) continue;
        ++st->solved;
        ++st->converged;
        st->first_s.push_back(cpu_s);
        st->total_s.push_back(cpu_s);
        st->length.push_back(res.length_cells);
        st->angle.push_back(polylineAngleChange(res.path));
        if (!dump_dir.empty() && r == 0) dumpPath(dump_dir + "/" + c.name + "_" + (st == &theta ? "theta" : "astar") + ".txt", res.path);
      }
    }
    printRow("A* (8-conn.)", astar, runs);
    printRow("Theta*", theta, runs);
    const long long rrt_budget = rrt_iterations < 0 ? static_cast<long long>(c.rrt_iterations) : rrt_iterations;
    if (rrt_budget > 0) rrtStarLospoRow(grid, c.start, c.goal, runs, static_cast<std::uint64_t>(rrt_budget));
    const double reference = mean(theta.length);
    if (!hab) continue;
    // The two planners alternate run by run (seed s of HAB-PP, then seed s of Improved HAB-PP), so
    // a change of the machine's load during the benchmark weighs on both alike.
    struct Row {
      HabPpParameters params;
      Stats s;
      double iterations = 0.0, first_iteration = 0.0;
      std::vector<double> ranked_length;  // before the output stage
      int first_by_rrt = 0, first_by_join = 0;
      double rrt_paths = 0.0, joined_paths = 0.0;
    };
    Row rows[2];
    for (int k = 0; k < 2; ++k) {
      HabPpParameters& params = rows[k].params;
      params = k == 0 ? HabPpParameters{} : published ? HabPpParameters::improvedAsPublished() : HabPpParameters::improved();
      if (stable > 0) params.stable_iterations = stable;
      if (near_k >= 0) params.rrt_near_nearest = near_k != 0;
      if (output_routes > 0) params.output_ranked_routes = output_routes;
      if (stop_top >= 0) params.rrt_stop_top_paths = stop_top != 0;
      if (draws > 0) params.rrt_draws_per_step = draws;
      if (shared_tree >= 0) params.rrt_shared_tree = shared_tree != 0;
      if (sample_eta >= 0) params.rrt_sample_visibility = sample_eta != 0;
      if (corridor >= -1) params.output_corridor_cells = corridor;
      if (after_solution >= 0) params.rrt_nodes_after_solution = after_solution;
      if (rest >= 0) params.rrt_rest_when_full = rest != 0;
      if (node_redraws >= 0) params.rrt_node_redraws = node_redraws;
      if (tree_route >= 0) params.output_tree_route = tree_route != 0;
      if (tau_min > 0.0) params.pheromone_min = tau_min;
      if (window >= 0.0) params.output_window_cells = window;
      if (window_segments >= 0) params.output_window_segments = window_segments;
      if (window_margin >= 0) params.output_window_margin_cells = window_margin;
      if (weights[0] >= 0.0) {
        params.w_length = weights[0];
        params.w_angle = weights[1];
        params.w_points = weights[2];
      }
    }
    std::vector<double> first_ratio, total_ratio;  // Improved / HAB-PP per seed, both found
    for (int r = 0; r < runs; ++r) {
      double first[2] = {-1.0, -1.0}, total[2] = {-1.0, -1.0};
      for (int k = 0; k < 2; ++k) {
        if (only >= 0 && k != only) continue;
        Row& row = rows[k];
        const HabPpResult res = planHabPp(grid, c.start, c.goal, row.params, 1000 + static_cast<std::uint64_t>(r),
                                          TerminationCondition::after(std::chrono::nanoseconds(
                                              static_cast<std::int64_t>(budget_s * 1e9))));
        if (res.first_path_cpu_s >= 0.0) row.s.first_s.push_back(res.first_path_cpu_s);
        row.iterations += static_cast<double>(res.iterations) / runs;
        row.first_iteration += static_cast<double>(res.first_path_iteration) / runs;
        if (!hasPath(res.status)) continue;
        if (!dump_dir.empty()) dumpPath(dump_dir + "/" + c.name + "_" + std::to_string(k) + "_" + std::to_string(r) + ".txt", res.path);
        first[k] = res.first_path_cpu_s;
        total[k] = res.total_cpu_s;
        ++row.s.solved;
        if (res.status == PlannerStatus::kSolved) ++row.s.converged;
        row.s.total_s.push_back(res.total_cpu_s);
        row.s.length.push_back(res.length_cells);
        row.s.angle.push_back(res.angle_change_rad);
        row.ranked_length.push_back(res.ranked_length_cells);
        row.first_by_rrt += res.first_path_by_rrt ? 1 : 0;
        row.first_by_join += res.first_path_by_join ? 1 : 0;
        row.rrt_paths += static_cast<double>(res.rrt_arrivals) / runs;
        row.joined_paths += static_cast<double>(res.joined_arrivals) / runs;
      }
      if (first[0] > 0.0 && first[1] > 0.0) {
        first_ratio.push_back(first[1] / first[0]);
        total_ratio.push_back(total[1] / total[0]);
      }
    }
    for (int k = 0; k < 2; ++k) {
      const Row& row = rows[k];
      const Stats& s = row.s;
      printRow(k == 1 ? "Improved HAB-PP" : "HAB-PP", s, runs);
      std::printf("|   (details) | length vs Theta*: mean %+.2f%%, best %+.2f%% (best ranked path before the output "
                  "stage: mean %+.2f%%, best %+.2f%%); iterations: first path %.0f, total %.0f; first path by the "
                  "RRT* species in %d runs, by an ant finishing along a tree in %d runs; RRT* paths per run %.1f, "
                  "paths finished along a tree per run %.1f |\n",
                  100.0 * (mean(s.length) / reference - 1.0), 100.0 * (minOf(s.length) / reference - 1.0),
                  100.0 * (mean(row.ranked_length) / reference - 1.0), 100.0 * (minOf(row.ranked_length) / reference - 1.0),
                  row.first_iteration, row.iterations, row.first_by_rrt, row.first_by_join, row.rrt_paths,
                  row.joined_paths);
    }
    printBoxPlots(rows[0].s, rows[1].s);
    std::printf("\nImproved vs HAB-PP: mean times %+.1f%% first path, %+.1f%% total; per seed (both found, %zu "
                "seeds) median ratio %+.1f%% first path, %+.1f%% total\n",
                100.0 * (mean(rows[1].s.first_s) / mean(rows[0].s.first_s) - 1.0),
                100.0 * (mean(rows[1].s.total_s) / mean(rows[0].s.total_s) - 1.0), first_ratio.size(),
                100.0 * (median(first_ratio) - 1.0), 100.0 * (median(total_ratio) - 1.0));
    std::fflush(stdout);
  }
  return 0;
}
