#include "service/planner_registry.hpp"

#include <algorithm>
#include <array>
#include <chrono>

namespace skyroute {
namespace {

const std::array<RoutePlannerInfo, 3>& table() {
  static const std::array<RoutePlannerInfo, 3> planners{{
      {RoutePlannerKind::kRrtStarLospo, kDefaultRoutePlanner,
       "RRT* in 3D in a corridor around each leg, shortened by LOSPO (seed 003)",
       {"planning.corridor_margin_m", "planning.lospo_spacing_m"},
       {"rrtstar_lospo"}},
      {RoutePlannerKind::kHabPp, "hab-pp",
       "HAB-PP: heterogeneous ant colonies on the flight band's grid, lifted to 3D (seed 004)",
       {"planning.grid_max_cells", "planning.grid_band_margin_m", "planning.grid_window_segments"},
       {}},
      {RoutePlannerKind::kHabPpRrt, "hab-pp-rrt",
       "Improved HAB-PP: ants and RRT* sharing one pheromone field on the flight band's grid (seed 004)",
       {"planning.grid_max_cells", "planning.grid_band_margin_m", "planning.grid_window_segments"},
       {}},
  }};
  return planners;
}

}  // namespace

std::span<const RoutePlannerInfo> routePlanners() { return table(); }

const RoutePlannerInfo& routePlanner(RoutePlannerKind kind) {
  for (const RoutePlannerInfo& p : table()) {
    if (p.kind == kind) return p;
  }
  return table().front();
}

std::string routePlannerNames(std::string_view separator) {
  std::string names;
  for (const RoutePlannerInfo& p : table()) {
    if (!names.empty()) names += separator;
    names += p.name;
  }
  return names;
}

std::optional<PlanError> findRoutePlanner(std::string_view name, const RoutePlannerInfo** found,
                                          const std::string& field) {
  for (const RoutePlannerInfo& p : table()) {
    const bool alias = std::find(p.aliases.begin(), p.aliases.end(), name) != p.aliases.end();
    if (p.name == name || alias) {
      if (found) *found = &p;
      return std::nullopt;
    }
  }
  return PlanError{PlanErrorCode::kUnknownPlanner, field,
                   "'" + std::string(name) + "' is not a known planner (known: " + routePlannerNames() + ")"};
}

LegPathPlanner legPathPlanner(RoutePlannerKind kind, const GridLegOptions& grid) {
  if (kind == RoutePlannerKind::kRrtStarLospo) {
    return [](std::shared_ptr<const CollisionWorld> world, const std::vector<Eigen::Vector3d>& points_m,
              const RouteOptions& options, const TerminationCondition& stop) {
      return planRoutePaths(std::move(world), points_m, options, stop);
    };
  }
  const GridGlobalPlanner planner = kind == RoutePlannerKind::kHabPp ? GridGlobalPlanner::kHabPp : GridGlobalPlanner::kHabPpRrt;
  return [planner, grid](std::shared_ptr<const CollisionWorld> world, const std::vector<Eigen::Vector3d>& points_m,
                         const RouteOptions& options, const TerminationCondition& stop) {
    // One budget for every planner: the legs' wall-clock cap is the route's.
    GridLegOptions leg_options = grid;
    leg_options.leg_time_cap_s = options.leg_budget_ms * 1e-3;
    leg_options.max_path_climb_deg = options.max_path_climb_deg;
    leg_options.max_path_descent_deg = options.max_path_descent_deg;
    return planGridRoutePaths(std::move(world), points_m, planner, leg_options, options.seed, stop, options.snapshot);
  };
}

}  // namespace skyroute
