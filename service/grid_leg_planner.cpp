#include "service/grid_leg_planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>
#include <string_view>

#include <spdlog/spdlog.h>

#include "planning/colony/hab_pp.hpp"
#include "service/planner_status.hpp"
#include "terrain/grid_from_terrain.hpp"

namespace skyroute {

namespace {

std::string legName(std::size_t i) { return "legs[" + std::to_string(i) + "]"; }

// How many times a leg's band may rise by its margin before the leg is given up (each costs a
// grid of at most max_cells_per_axis^2 cells and a connectivity check).
constexpr int kMaxBandRaises = 20;

std::string_view plannerName(GridGlobalPlanner planner) {
  return planner == GridGlobalPlanner::kHabPp ? "hab-pp" : "hab-pp-rrt";
}

// The first piece of `path` steeper than the options' path angles allow, if any.
std::optional<std::size_t> steeperThanAllowed(const std::vector<Eigen::Vector3d>& path, const GridLegOptions& options) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  for (std::size_t k = 0; k + 1 < path.size(); ++k) {
    const Eigen::Vector3d d = path[k + 1] - path[k];
    const double limit_deg = d.z() > 0.0 ? options.max_path_climb_deg : options.max_path_descent_deg;
    if (limit_deg <= 0.0 || d.z() == 0.0) continue;
    // A tolerance for the lifting's own rounding.
    if (std::abs(d.z()) > std::tan(limit_deg * kDeg) * d.head<2>().norm() * (1.0 + 1e-6) + 1e-6) return k;
  }
  return std::nullopt;
}

}  // namespace

Result<PlannedRoute> planGridRoutePaths(std::shared_ptr<const CollisionWorld> world,
                                        const std::vector<Eigen::Vector3d>& points_m, GridGlobalPlanner planner,
                                        const GridLegOptions& options, std::uint64_t seed,
                                        const TerminationCondition& stop, std::optional<ObstacleSnapshot> snapshot) {
  const auto started = std::chrono::steady_clock::now();
  if (!world) return make_error(ErrorCode::kInvalidArgument, "world", "is null");
  if (points_m.size() < 2) return make_error(ErrorCode::kInvalidArgument, "points", "a route needs two points");
  const Heightfield& terrain = world->terrain();
  const CollisionWorldOptions& wo = world->options();
  auto valid = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return snapshot ? world->isSegmentValid(a, b, *snapshot) : world->isSegmentValid(a, b);
  };
  HabPpParameters params = planner == GridGlobalPlanner::kHabPpRrt ? HabPpParameters::improved() : HabPpParameters{};
  params.output_window_segments = options.output_window_segments;
  const double cell_m = std::max(terrain.dem().resolutionM().minCoeff(),
                                 1.0001 * terrain.boundsEn().sizes().maxCoeff() / std::max(8, options.max_cells_per_axis));
  PlannedRoute route;
  for (std::size_t i = 0; i + 1 < points_m.size(); ++i) {
    const Eigen::Vector3d& a = points_m[i];
    const Eigen::Vector3d& b = points_m[i + 1];
    RouteLeg leg;
    leg.from_point = i;
    leg.to_point = i + 1;
    if (valid(a, b)) {
      leg.path_m = {a, b};  // the straight leg is clear: nothing for a global planner to do
    } else {
      // The band: from the ground clearance up to above the higher end, under the ceiling. When
      // terrain above it parts the ends (the connectivity check says so at once), the band
      // rises by its margin again, up to the ceiling: a ridge between the ends is flown over.
      const double lowest_top_m = std::min(wo.ceiling_m - 1.0, std::max(a.z(), b.z()) + options.band_margin_m);
      double band_top_m = lowest_top_m;
      std::optional<GridLayer> grid;
      std::optional<GridCell> start, goal;
      HabPpResult found;
      TerminationCondition leg_stop = stop;
      if (options.leg_time_cap_s > 0.0) {
        leg_stop.withDeadlineAfter(std::chrono::nanoseconds(static_cast<std::int64_t>(options.leg_time_cap_s * 1e9)));
      }
      for (int raise = 0;; ++raise) {
        band_top_m = std::min(wo.ceiling_m - 1.0, lowest_top_m + raise * std::max(options.band_margin_m, 50.0));
        TerrainGridOptions grid_options;
        grid_options.cell_size_m = cell_m;
        grid_options.flight_ceiling_m = band_top_m;
        grid_options.min_clearance_m = wo.min_clearance_m + wo.vehicle_radius_m;
        grid_options.cancel = stop.cancelFlag();
        grid_options.no_fly_zones = world->noFlyZones();
        grid_options.zone_margin_m = wo.vehicle_radius_m;
        grid_options.keep_free_m = {a.head<2>(), b.head<2>()};
        auto built_grid = buildTerrainGrid(terrain, grid_options);
        if (!built_grid.ok()) return built_grid.error();
        grid.emplace(std::move(*built_grid));
        start = grid->cellAt(a.head<2>());
        goal = grid->cellAt(b.head<2>());
        if (!start || !goal) return make_error(ErrorCode::kOutsideMap, legName(i), "an end of the leg is off the flight-band grid");
        found = planHabPp(*grid, *start, *goal, params, seed + i, leg_stop);
        if (found.status != PlannerStatus::kNoPath || band_top_m >= wo.ceiling_m - 1.0 || raise >= kMaxBandRaises) break;
      }
      // The caller's own deadline is not this leg's cap.
      leg.time_capped = found.stop_reason == TerminationCondition::Reason::kDeadline && !stop.shouldStop();
      if (found.stop_reason == TerminationCondition::Reason::kCancelled)
        return plannerError(PlannerStatus::kCancelled, legName(i), "cancelled");
      if (!hasPath(found.status)) {
        // The leg's own cap is part of its budget: no path within it.
        const PlannerStatus status = isStopped(found.status) ? PlannerStatus::kBudgetExhausted : found.status;
        return plannerError(status, legName(i),
                            std::string(to_string(found.status)) + " on the flight band under " +
                              std::to_string(static_cast<int>(band_top_m)) + " m" +
                              (found.message.empty() ? "" : ": " + found.message));
      }
      // Lift: the interior vertices at the band altitude (cell centres), the ends as given.
      const double cruise_m = band_top_m;
      std::vector<Eigen::Vector3d> lifted{a};
      for (std::size_t k = 1; k + 1 < found.path.size(); ++k) {
        const Eigen::Vector2d en = grid->cellCenter(found.path[k]);
        lifted.emplace_back(en.x(), en.y(), cruise_m);
      }
      lifted.push_back(b);
      // Climb over the start and descend over the end where the direct slope is blocked.
      std::vector<Eigen::Vector3d> path{a};
      for (std::size_t k = 1; k < lifted.size(); ++k) {
        const Eigen::Vector3d& from = path.back();
        const Eigen::Vector3d& to = lifted[k];
        if (!valid(from, to)) {
          const Eigen::Vector3d up_here(from.x(), from.y(), cruise_m);
          const Eigen::Vector3d up_there(to.x(), to.y(), cruise_m);
          if (from.z() < cruise_m && valid(from, up_here) && valid(up_here, to)) {
            path.push_back(up_here);
          } else if (to.z() < cruise_m && valid(from, up_there) && valid(up_there, to)) {
            path.push_back(up_there);
          } else if (from.z() < cruise_m && to.z() < cruise_m && valid(from, up_here) && valid(up_here, up_there) &&
                     valid(up_there, to)) {
            path.push_back(up_here);
            path.push_back(up_there);
          } else {
            return make_error(ErrorCode::kUnreachable, legName(i),
                              "the grid path lifted to the band is blocked between vertices " +
                                  std::to_string(k - 1) + " and " + std::to_string(k));
          }
        }
        path.push_back(to);
      }
      leg.path_m = std::move(path);
    }
    if (auto steep = steeperThanAllowed(leg.path_m, options)) {
      const bool climbs = leg.path_m[*steep + 1].z() > leg.path_m[*steep].z();
      const Eigen::Vector3d d = leg.path_m[*steep + 1] - leg.path_m[*steep];
      const double angle_deg = std::atan2(std::abs(d.z()), d.head<2>().norm()) * 180.0 / std::numbers::pi;
      return make_error(ErrorCode::kInvalidArgument, "planner",
                        fmt::format("{}'s path of {} {} at {:.1f} deg between its vertices {} and {} (the grid path is "
                                    "lifted to the flight band over the leg's ends), steeper than the fixed wing's "
                                    "{:.1f} deg path angle: plan a fixed wing with rrtstar-lospo",
                                    plannerName(planner), legName(i), climbs ? "climbs" : "descends", angle_deg, *steep,
                                    *steep + 1,
                                    climbs ? options.max_path_climb_deg : options.max_path_descent_deg));
    }
    double length = 0.0;
    for (std::size_t k = 1; k < leg.path_m.size(); ++k) length += (leg.path_m[k] - leg.path_m[k - 1]).norm();
    leg.lospo_length_m = length;
    leg.rrt.length_m = length;
    for (std::size_t k = (i == 0 ? 0 : 1); k < leg.path_m.size(); ++k) route.waypoints_m.push_back(leg.path_m[k]);
    route.legs.push_back(std::move(leg));
  }
  route.planning_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return route;
}

}  // namespace skyroute
