#include "planning/colony/hab_pp.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <string>

#include "planning/colony/hab_pp_colony.hpp"
#include "planning/colony/hab_pp_output.hpp"
#include "planning/grid/any_angle_search.hpp"
#include "planning/grid/grid_search.hpp"

namespace skyroute {

std::string_view to_string(HabPpStatus status) {
  switch (status) {
    case HabPpStatus::kConverged: return "converged";
    case HabPpStatus::kStoppedWithPath: return "stopped with path";
    case HabPpStatus::kStoppedWithoutPath: return "stopped without path";
    case HabPpStatus::kInvalidStart: return "invalid start";
    case HabPpStatus::kInvalidGoal: return "invalid goal";
    case HabPpStatus::kUnreachable: return "unreachable";
    case HabPpStatus::kInvalidParameters: return "invalid parameters";
  }
  return "unknown";
}

Status HabPpParameters::validate() const {
  auto bad = [](const char* field, const std::string& why) {
    return Status(make_error(ErrorCode::kInvalidArgument, field, std::string(field) + ": " + why));
  };
  const std::pair<const char*, int> counts[] = {
      {"simple_ants", simple_ants},         {"general_ants", general_ants},
      {"far_sighted_ants", far_sighted_ants}, {"sight_general_ants", sight_general_ants},
      {"sight_far_sighted_ants", sight_far_sighted_ants}, {"rrt_ants", rrt_ants},
      {"crossover_paths", crossover_paths}, {"max_ant_steps", max_ant_steps},
      {"crossover_points", crossover_points}, {"tighten_passes", tighten_passes}};
  for (const auto& [field, value] : counts) {
    if (value < 0) return bad(field, "must be >= 0, got " + std::to_string(value));
  }
  if (totalAnts() + rrt_ants == 0) return bad("simple_ants", "the colony has no ant of any species");
  if (ranked_paths < 1) return bad("ranked_paths", "must be >= 1");
  const std::pair<const char*, double> non_negative[] = {
      {"alpha", alpha}, {"beta", beta}, {"gamma", gamma}, {"w_length", w_length}, {"w_angle", w_angle},
      {"w_points", w_points}};
  for (const auto& [field, value] : non_negative) {
    if (!std::isfinite(value) || value < 0.0) return bad(field, "must be finite and >= 0");
  }
  if (!(w_length + w_angle + w_points > 0.0)) return bad("w_length", "the weights of eq. (2) sum to 0");
  if (!(rho > 0.0 && rho < 1.0)) return bad("rho", "must lie in (0, 1)");
  if (!(k_mix >= 0.0 && k_mix <= 1.0)) return bad("k_mix", "must lie in [0, 1]");
  if (!(d0_cells > 0.0) || !std::isfinite(d0_cells)) return bad("d0_cells", "must be > 0");
  if (!(rrt_step_cells >= 1.0) || !std::isfinite(rrt_step_cells)) return bad("rrt_step_cells", "must be >= 1");
  if (!(rrt_near_radius_cells >= 1.0) || !std::isfinite(rrt_near_radius_cells)) {
    return bad("rrt_near_radius_cells", "must be >= 1");
  }
  if (general_radius < 1) return bad("general_radius", "must be >= 1");
  if (far_sighted_radius < 1) return bad("far_sighted_radius", "must be >= 1");
  if (sight_max_radius < std::max(general_radius, far_sighted_radius)) {
    return bad("sight_max_radius", "must be >= general_radius and far_sighted_radius");
  }
  if (!(pheromone_min > 0.0 && pheromone_min <= pheromone_max) || !std::isfinite(pheromone_max)) {
    return bad("pheromone_min", "need 0 < pheromone_min <= pheromone_max");
  }
  if (!(angle_factor_floor > 0.0 && angle_factor_floor <= 1.0)) return bad("angle_factor_floor", "must lie in (0, 1]");
  if (!(angle_eval_epsilon_rad > 0.0) || !std::isfinite(angle_eval_epsilon_rad)) {
    return bad("angle_eval_epsilon_rad", "must be > 0");
  }
  if (output_corridor_cells < -1) return bad("output_corridor_cells", "must be >= -1");
  if (!(output_window_cells >= 0.0) || !std::isfinite(output_window_cells)) {
    return bad("output_window_cells", "must be >= 0 (0: no windowed re-planning)");
  }
  if (output_window_segments < 0) return bad("output_window_segments", "must be >= 0 (0: no windowed re-planning)");
  if (output_window_margin_cells < 0) return bad("output_window_margin_cells", "must be >= 0");
  if (output_ranked_routes < 1) return bad("output_ranked_routes", "must be >= 1");
  if (stable_iterations < 1) return bad("stable_iterations", "must be >= 1");
  if (rrt_nodes_after_solution < 0) return bad("rrt_nodes_after_solution", "must be >= 0 (0: never restart)");
  if (rrt_draws_per_step < 1) return bad("rrt_draws_per_step", "must be >= 1");
  if (rrt_node_redraws < 0) return bad("rrt_node_redraws", "must be >= 0");
  if (rrt_ants_join_tree && !rrt_tree_from_goal) {
    return bad("rrt_ants_join_tree", "needs rrt_tree_from_goal (an ant can only finish along a tree that ends at the goal)");
  }
  return Status::success();
}

namespace {

// The output stage (hab_pp_output.hpp) once the colony stops: the top ranked routes, plus the
// shortest path ever ranked and the best tree path when those are asked for, made taut in their
// corridor and then re-planned in windows.
habpp::Path outputPath(const GridLayer& grid, const habpp::Colony& colony, const HabPpParameters& params) {
  const std::vector<habpp::Path>& ranked = colony.ranked();
  const std::size_t count = std::min<std::size_t>(ranked.size(), static_cast<std::size_t>(params.output_ranked_routes));
  std::vector<habpp::Path> routes(ranked.begin(), ranked.begin() + static_cast<std::ptrdiff_t>(count));
  auto offer = [&routes](const habpp::Path& route) {
    if (!route.empty() && std::find(routes.begin(), routes.end(), route) == routes.end()) routes.push_back(route);
  };
  if (params.output_ranked_routes > 1) offer(colony.shortestRanked());
  if (params.output_tree_route) offer(colony.bestTreePath());
  const habpp::Path taut = params.output_corridor_cells >= 0
                               ? habpp::tautPath(grid, routes, params.output_corridor_cells, params.tighten_passes)
                               : ranked.front();
  return habpp::replanWindows(grid, taut,
                              habpp::WindowOptions{.segments = params.output_window_segments,
                                                   .span_cells = params.output_window_cells,
                                                   .margin_cells = params.output_window_margin_cells},
                              params.tighten_passes);
}

}  // namespace

HabPpResult planHabPp(const GridLayer& grid, GridCell start, GridCell goal, const HabPpParameters& params,
                      std::uint64_t seed, const TerminationCondition& stop) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  auto cpu_seconds = [&] { return static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC; };
  HabPpResult result;
  auto fail = [&](HabPpStatus status, std::string message) {
    result.status = status;
    result.message = std::move(message);
    result.total_time_s = seconds();
    result.total_cpu_s = cpu_seconds();
    return result;
  };
  if (const Status valid = params.validate(); !valid) return fail(HabPpStatus::kInvalidParameters, valid.error().describe());
  auto where = [](GridCell c) { return "(" + std::to_string(c.x) + ", " + std::to_string(c.y) + ")"; };
  if (!grid.inside(start)) return fail(HabPpStatus::kInvalidStart, "start: " + where(start) + " is outside the grid");
  if (grid.blocked(start)) return fail(HabPpStatus::kInvalidStart, "start: " + where(start) + " is blocked");
  if (!grid.inside(goal)) return fail(HabPpStatus::kInvalidGoal, "goal: " + where(goal) + " is outside the grid");
  if (grid.blocked(goal)) return fail(HabPpStatus::kInvalidGoal, "goal: " + where(goal) + " is blocked");
  if (start == goal) {
    result.status = HabPpStatus::kConverged;
    result.path = {start};
    result.first_path_time_s = seconds();
    result.total_time_s = result.first_path_time_s;
    return result;
  }
  // 8-connected without corner cutting: exactly the cells an any-angle path can reach, since a
  // segment that passes lineOfSight steps through side- or corner-adjacent free cells.
  if (reachableCells(grid, start)[grid.index(goal)] == 0) {
    return fail(HabPpStatus::kUnreachable, "goal: no free path joins start " + where(start) + " and goal " + where(goal));
  }

  habpp::Rng rng(seed);
  habpp::Colony colony(grid, start, goal, params, seed);
  int unchanged = 0;
  int unchanged_with_arrivals = 0;
  for (;;) {
    const auto reason = stop.reason(result.iterations);
    if (reason != TerminationCondition::Reason::kNone) {
      result.stop_reason = reason;
      result.status = colony.ranked().empty() ? HabPpStatus::kStoppedWithoutPath : HabPpStatus::kStoppedWithPath;
      break;
    }
    ++result.iterations;
    const std::uint64_t arrivals_before = result.ant_arrivals + result.rrt_arrivals;
    const bool changed = colony.iterate(rng, result);
    if (result.first_path_time_s < 0.0 && !colony.ranked().empty()) {
      result.first_path_time_s = seconds();
      result.first_path_cpu_s = cpu_seconds();
      result.first_path_iteration = result.iterations;
      result.first_path_by_rrt = result.rrt_arrivals > 0;
      result.first_path_by_join = result.joined_arrivals > 0;
    }
    // Table 2's termination: the ranked list stops changing. Choice: unchanged for
    // stable_iterations iterations once it holds N_R paths; while it holds fewer (a small map may
    // not have N_R distinct paths), unchanged for stable_iterations iterations in which some path
    // arrived, so a long search for the first few paths does not end the plan.
    const bool arrived = result.ant_arrivals + result.rrt_arrivals > arrivals_before;
    unchanged = changed ? 0 : unchanged + 1;
    unchanged_with_arrivals = changed ? 0 : unchanged_with_arrivals + (arrived ? 1 : 0);
    const bool full = colony.ranked().size() >= static_cast<std::size_t>(params.ranked_paths);
    if (!colony.ranked().empty() &&
        (full ? unchanged >= params.stable_iterations : unchanged_with_arrivals >= params.stable_iterations)) {
      result.status = HabPpStatus::kConverged;
      break;
    }
  }
  if (!colony.ranked().empty()) {
    result.ranked_length_cells = polylineLength(colony.ranked().front());
    result.path = outputPath(grid, colony, params);
    result.length_cells = polylineLength(result.path);
    result.angle_change_rad = polylineAngleChange(result.path);
  } else {
    result.message = "no ant reached the goal before the termination condition (" +
                     std::string(to_string(result.stop_reason)) + ")";
  }
  result.total_time_s = seconds();
  result.total_cpu_s = cpu_seconds();
  return result;
}

}  // namespace skyroute

