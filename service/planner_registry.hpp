// The route planners a mission may name. Each is registered once, here, under one name with its
// summary and the configuration keys that tune it; every user-facing list takes its names from
// this table: the CLI's --planner, the mission JSON's "planner", the configuration's
// planning.default_planner, `skyroute planners`, the benchmark tables and the docs.
//
// A route planner finds the 3D paths of a route's legs through points already in visiting order;
// the trajectory stage after it is the same for every planner (route_planner.hpp).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "service/grid_leg_planner.hpp"
#include "service/mission_types.hpp"
#include "service/route_planner.hpp"

namespace skyroute {

enum class RoutePlannerKind { kRrtStarLospo, kHabPp, kHabPpRrt };

struct RoutePlannerInfo {
  RoutePlannerKind kind;
  std::string_view name;      // the one spelling users write
  std::string_view summary;   // one line: what it does and where it comes from
  std::vector<std::string_view> config_keys;  // the keys that tune it (besides planning.leg_*)
  std::vector<std::string_view> aliases;      // older spellings still accepted
};

// Every registered planner, the default first.
std::span<const RoutePlannerInfo> routePlanners();
const RoutePlannerInfo& routePlanner(RoutePlannerKind kind);
inline constexpr std::string_view kDefaultRoutePlanner = "rrtstar-lospo";

// The planner of that name or alias. An unknown name is kUnknownPlanner on `field`, and the
// message lists the known names.
std::optional<PlanError> findRoutePlanner(std::string_view name, const RoutePlannerInfo** found,
                                          const std::string& field = "planner");
// "rrtstar-lospo, hab-pp, hab-pp-rrt"
std::string routePlannerNames(std::string_view separator = ", ");

// How the planner of `kind` plans a route's legs (the grid planners read `grid`).
LegPathPlanner legPathPlanner(RoutePlannerKind kind, const GridLegOptions& grid);

}  // namespace skyroute
