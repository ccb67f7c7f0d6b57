#include "service/fleet_mission.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>

#include <spdlog/spdlog.h>

#include "planning/fleet_planner.hpp"
#include "service/trajectory_data.hpp"
#include "terrain/grid_from_terrain.hpp"

namespace skyroute {

namespace {

std::string indexed(const char* name, std::size_t i) { return std::string(name) + "[" + std::to_string(i) + "]"; }

PlanError fail(PlanErrorCode code, std::string field, std::string message) {
  return PlanError{code, std::move(field), std::move(message)};
}

std::optional<PlanError> checkPoint(const MissionPointData& p, const std::string& field) {
  if (p.frame == MissionPointData::Frame::kWgs84) {
    if (!std::isfinite(p.geo.lat_deg) || std::abs(p.geo.lat_deg) > 90.0)
      return fail(PlanErrorCode::kInvalidArgument, field + ".lat_deg", "must be a latitude in [-90, 90]");
    if (!std::isfinite(p.geo.lon_deg) || std::abs(p.geo.lon_deg) > 180.0)
      return fail(PlanErrorCode::kInvalidArgument, field + ".lon_deg", "must be a longitude in [-180, 180]");
    if (!std::isfinite(p.geo.alt_amsl_m))
      return fail(PlanErrorCode::kInvalidArgument, field + ".alt_amsl_m", "is not a finite number");
  } else if (!p.enu_m.allFinite()) {
    return fail(PlanErrorCode::kInvalidArgument, field + ".enu_m", "is not a finite position");
  }
  return std::nullopt;
}

// GMTPA names items "vehicle <id>" / "task <id>" (optionally with a suffix); the ids are the
// request's field names, so the reply names "begins[i]" or "tasks[j]".
std::string requestField(const std::string& field) {
  std::string rest = field;
  for (const char* prefix : {"vehicle ", "task "}) {
    if (rest.rfind(prefix, 0) == 0) rest = rest.substr(std::string(prefix).size());
  }
  if (const auto space = rest.find(' '); space != std::string::npos) rest = rest.substr(0, space);
  return rest;
}

bool nearlyEqual2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return (a - b).norm() < 1e-6; }

}  // namespace

Eigen::Vector3d FleetPlanOutput::positionAt(std::size_t i, double t_s) const {
  const double local = t_s - delays_s[i];
  if (local <= 0.0) return flown[i].evaluate(0.0, Derivative::kPosition);
  if (local >= flown[i].duration_s()) return flown[i].evaluate(flown[i].duration_s(), Derivative::kPosition);
  return flown[i].evaluate(local, Derivative::kPosition);
}

std::optional<PlanError> validateFleetRequest(const FleetRequestData& r, const FleetMissionOptions& options) {
  if (r.request_id.empty()) return fail(PlanErrorCode::kInvalidArgument, "request_id", "is empty");
  if (r.vehicle_ids.empty()) return fail(PlanErrorCode::kEmptyMission, "vehicle_ids", "no vehicles given");
  if (r.vehicle_ids.size() > options.max_vehicles) {
    return fail(PlanErrorCode::kMissionTooLarge, "vehicle_ids",
                std::to_string(r.vehicle_ids.size()) + " vehicles, at most " + std::to_string(options.max_vehicles));
  }
  std::set<std::string> seen;
  for (std::size_t i = 0; i < r.vehicle_ids.size(); ++i) {
    if (r.vehicle_ids[i].empty()) return fail(PlanErrorCode::kInvalidArgument, indexed("vehicle_ids", i), "is empty");
    if (!seen.insert(r.vehicle_ids[i]).second) {
      return fail(PlanErrorCode::kInvalidArgument, indexed("vehicle_ids", i), "duplicate vehicle id '" + r.vehicle_ids[i] + "'");
    }
  }
  if (r.begins.size() != r.vehicle_ids.size()) {
    return fail(PlanErrorCode::kInvalidArgument, "begins",
                "has " + std::to_string(r.begins.size()) + " points for " + std::to_string(r.vehicle_ids.size()) + " vehicles");
  }
  if (r.ends.size() != r.vehicle_ids.size()) {
    return fail(PlanErrorCode::kInvalidArgument, "ends",
                "has " + std::to_string(r.ends.size()) + " points for " + std::to_string(r.vehicle_ids.size()) + " vehicles");
  }
  if (r.tasks.empty()) return fail(PlanErrorCode::kEmptyMission, "tasks", "no tasks given");
  if (r.tasks.size() > options.max_tasks) {
    return fail(PlanErrorCode::kMissionTooLarge, "tasks",
                std::to_string(r.tasks.size()) + " tasks, at most " + std::to_string(options.max_tasks));
  }
  for (std::size_t i = 0; i < r.begins.size(); ++i) {
    if (auto e = checkPoint(r.begins[i], indexed("begins", i))) return e;
    if (auto e = checkPoint(r.ends[i], indexed("ends", i))) return e;
  }
  for (std::size_t j = 0; j < r.tasks.size(); ++j) {
    if (auto e = checkPoint(r.tasks[j], indexed("tasks", j))) return e;
  }
  if (Status ok = toVehicleLimits(r.limits).validate(); !ok.ok()) {
    std::string field = ok.error().field;
    if (field == "limits.max_climb_mps") field = "limits.max_climb_rate_mps";
    if (field == "limits.max_descent_mps") field = "limits.max_descent_rate_mps";
    return fail(PlanErrorCode::kLimitsOutOfRange, field, ok.error().message);
  }
  if (!r.planner.empty() && r.planner != kFleetPlannerGreedy) {
    return fail(PlanErrorCode::kUnknownPlanner, "planner",
                "'" + r.planner + "' is not a fleet planner (\"\" or \"" + kFleetPlannerGreedy + "\")");
  }
  return std::nullopt;
}

namespace {

// The planning proper; throws nothing, reports through `out.status` (error fields) or fills out.
std::optional<PlanError> planInto(const FleetRequestData& r, WorldModel& world_model, const FleetMissionOptions& o,
                                  std::int64_t start_utc_ns, const TerminationCondition& stop, FleetPlanOutput& out) {
  if (auto e = validateFleetRequest(r, o)) return e;
  if (!(o.separation_dt_s > 0.0) || !(o.delay_step_s > 0.0) || !(o.sample_dt_s > 0.0) || o.max_cells_per_axis < 4 ||
      !(o.min_separation_m >= 0.0)) {
    return fail(PlanErrorCode::kInternal, "options", "fleet options out of range");
  }
  auto world_r = world_model.worldFor(r.limits.min_clearance_agl_m, r.limits.ceiling_amsl_m);
  if (!world_r.ok()) return fail(PlanErrorCode::kLimitsOutOfRange, world_r.error().field, world_r.error().message);
  const std::shared_ptr<const CollisionWorld> world = *world_r;
  const LocalFrame& frame = world_model.frame();
  auto toEnu = [&](const MissionPointData& p) {
    return p.frame == MissionPointData::Frame::kWgs84 ? frame.toEnu(p.geo) : p.enu_m;
  };
  const std::size_t nv = r.vehicle_ids.size();
  const std::size_t nt = r.tasks.size();
  double top_m = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < nv; ++i) {
    out.begins_m.push_back(toEnu(r.begins[i]));
    out.ends_m.push_back(toEnu(r.ends[i]));
    if (Status ok = checkRoutePoint(*world, out.begins_m[i], indexed("begins", i)); !ok.ok()) return toPlanError(ok.error());
    if (Status ok = checkRoutePoint(*world, out.ends_m[i], indexed("ends", i)); !ok.ok()) return toPlanError(ok.error());
    top_m = std::max({top_m, out.begins_m[i].z(), out.ends_m[i].z()});
  }
  for (std::size_t j = 0; j < nt; ++j) {
    out.tasks_m.push_back(toEnu(r.tasks[j]));
    if (Status ok = checkRoutePoint(*world, out.tasks_m[j], indexed("tasks", j)); !ok.ok()) return toPlanError(ok.error());
    top_m = std::max(top_m, out.tasks_m[j].z());
  }

  // The flight band's grid (as the HAB-PP legs build theirs).
  const Heightfield& terrain = world_model.terrain();
  const CollisionWorldOptions& wo = world->options();
  out.cell_size_m = std::max(terrain.dem().resolutionM().minCoeff(),
                             1.0001 * terrain.boundsEn().sizes().maxCoeff() / o.max_cells_per_axis);
  out.cruise_altitude_m = std::min(wo.ceiling_m - 1.0, top_m + o.band_margin_m);
  const double cruise_m = out.cruise_altitude_m;
  TerrainGridOptions go;
  go.cell_size_m = out.cell_size_m;
  go.flight_ceiling_m = cruise_m;
  go.min_clearance_m = wo.min_clearance_m + wo.vehicle_radius_m;
  go.cancel = stop.cancelFlag();
  auto grid = buildTerrainGrid(terrain, go);
  if (!grid.ok()) return toPlanError(grid.error());
  const double separation_m = o.min_separation_m > 0.0 ? o.min_separation_m : out.cell_size_m;
  out.status.min_separation_m = separation_m;

  // Depots must already be apart: a held vehicle cannot be moved by a delay.
  for (std::size_t i = 0; i < nv; ++i) {
    for (std::size_t k = 0; k < i; ++k) {
      if ((out.begins_m[i] - out.begins_m[k]).norm() < separation_m) {
        return fail(PlanErrorCode::kInvalidArgument, indexed("begins", i),
                    "closer than the minimum separation (" + std::to_string(static_cast<int>(separation_m)) + " m) to begins[" +
                        std::to_string(k) + "]");
      }
      if ((out.ends_m[i] - out.ends_m[k]).norm() < separation_m) {
        return fail(PlanErrorCode::kInvalidArgument, indexed("ends", i),
                    "closer than the minimum separation (" + std::to_string(static_cast<int>(separation_m)) + " m) to ends[" +
                        std::to_string(k) + "]");
      }
    }
  }

  FleetProblem problem;
  for (std::size_t i = 0; i < nv; ++i) {
    const auto cell = grid->cellAt(out.begins_m[i].head<2>());
    if (!cell) return fail(PlanErrorCode::kOutsideMap, indexed("begins", i), "is off the flight-band grid");
    problem.vehicles.push_back({indexed("begins", i), *cell, 0});
  }
  for (std::size_t j = 0; j < nt; ++j) {
    const auto cell = grid->cellAt(out.tasks_m[j].head<2>());
    if (!cell) return fail(PlanErrorCode::kOutsideMap, indexed("tasks", j), "is off the flight-band grid");
    problem.tasks.push_back({indexed("tasks", j), *cell});
  }
  auto plan = planFleet(*grid, problem, FleetPlannerOptions{}, stop);
  if (!plan.ok()) {
    PlanError e = toPlanError(plan.error());
    e.field = requestField(plan.error().field);
    e.message = plan.error().message + " (on the " + std::to_string(static_cast<int>(out.cell_size_m)) +
                " m flight-band grid under " + std::to_string(static_cast<int>(cruise_m)) + " m)";
    return e;
  }
  out.status.makespan_steps = plan->makespan();

  // Each vehicle's route in 3D through the trajectory stage.
  const VehicleLimits limits = toVehicleLimits(r.limits);
  for (std::size_t i = 0; i < nv; ++i) {
    if (stop.shouldStop()) return fail(PlanErrorCode::kCancelled, "", "stopped while building trajectories");
    const VehiclePlan& vp = plan->paths.vehicles[i];
    const Eigen::Vector3d& begin = out.begins_m[i];
    const Eigen::Vector3d& end = out.ends_m[i];
    // The horizontal route: begin, the cells (a task's own position at its step), begin again.
    std::vector<Eigen::Vector2d> xy{begin.head<2>()};
    std::vector<int> route_point(1, 0);  // route point id per xy entry (-1 = plain cell), 0 = begin
    std::vector<GridCell> cell_of{vp.cells.front()};
    std::size_t next_task = 0;
    for (int t = 1; t <= vp.finish_step && t < static_cast<int>(vp.cells.size()); ++t) {
      const GridCell c = vp.cells[static_cast<std::size_t>(t)];
      cell_of.push_back(c);
      if (next_task < vp.tasks.size() && vp.task_steps[next_task] == t) {
        xy.push_back(out.tasks_m[static_cast<std::size_t>(vp.tasks[next_task])].head<2>());
        route_point.push_back(vp.tasks[next_task] + 1);
        ++next_task;
      } else {
        xy.push_back(t == vp.finish_step ? Eigen::Vector2d(begin.head<2>()) : grid->cellCenter(c));
        route_point.push_back(-1);
      }
    }
    if (next_task != vp.tasks.size()) return fail(PlanErrorCode::kInternal, indexed("vehicle_ids", i), "task steps out of order");
    // Waits and straight runs collapse: within one cell the route point (begin, task) stands for
    // the cell, and a plain cell is kept only where the route turns.
    std::vector<Eigen::Vector2d> kept_xy;
    std::vector<int> kept_id;
    GridCell last_cell{-1, -1};
    for (std::size_t k = 0; k < xy.size(); ++k) {
      const bool same_cell = !kept_xy.empty() && cell_of[k] == last_cell;
      last_cell = cell_of[k];
      if (same_cell && route_point[k] < 0) continue;
      if (same_cell && kept_id.back() < 0) {
        kept_xy.back() = xy[k];
        kept_id.back() = route_point[k];
        continue;
      }
      if (same_cell && nearlyEqual2(kept_xy.back(), xy[k])) {
        continue;  // two tasks at one position: one overflight does both (the second is not a new leg)
      }
      if (kept_xy.size() >= 2 && kept_id.back() < 0 && route_point[k] < 0) {
        const Eigen::Vector2d a = kept_xy[kept_xy.size() - 2];
        const Eigen::Vector2d b = kept_xy.back();
        const Eigen::Vector2d d1 = b - a;
        const Eigen::Vector2d d2 = xy[k] - b;
        if (std::abs(d1.x() * d2.y() - d1.y() * d2.x()) < 1e-6 * d1.norm() * d2.norm() && d1.dot(d2) > 0.0) {
          kept_xy.back() = xy[k];  // b lies on the straight line from a to here
          continue;
        }
      }
      kept_xy.push_back(xy[k]);
      kept_id.push_back(route_point[k]);
    }
    // Lift: climb over the begin, cruise, fly on to over the end, descend.
    std::vector<Eigen::Vector3d> points{begin};  // route points: begin, tasks (at cruise), end
    std::vector<std::vector<Eigen::Vector3d>> leg_paths(1, std::vector<Eigen::Vector3d>{begin});
    std::vector<std::uint32_t> order{0};
    auto add = [&](const Eigen::Vector3d& p) {
      if ((leg_paths.back().back() - p).norm() > 1e-6) leg_paths.back().push_back(p);
    };
    add(Eigen::Vector3d(begin.x(), begin.y(), cruise_m));
    for (std::size_t k = 1; k < kept_xy.size(); ++k) {
      const Eigen::Vector3d p(kept_xy[k].x(), kept_xy[k].y(), cruise_m);
      add(p);
      if (kept_id[k] > 0) {  // a task: a route point, and a new leg starts there
        points.push_back(p);
        order.push_back(static_cast<std::uint32_t>(kept_id[k]));
        leg_paths.push_back({p});
      }
    }
    if (vp.tasks.empty() && (end - begin).norm() < 1e-3) {
      // Idle: no tasks and home already. The vehicle stays where it is (a constant trajectory
      // of one sample interval) rather than climbing to the cruise altitude and back.
      Segment hold;
      hold.duration_s = o.sample_dt_s;
      for (int axis = 0; axis < 3; ++axis) {
        Polynomial7::Coefficients c{};
        c[0] = begin[axis];
        hold.axes[static_cast<std::size_t>(axis)] = Polynomial7(c);
      }
      out.flown.emplace_back(std::vector<Segment>{hold});
      TrajectoryData data;
      data.vehicle_id = r.vehicle_ids[i];
      data.visiting_order = {0, static_cast<std::uint32_t>(nt + 1)};
      data.legs.push_back(LegBoundaryData{0, static_cast<std::uint32_t>(nt + 1), 0.0, o.sample_dt_s});
      out.trajectories.push_back(std::move(data));
      out.status.allocation.push_back(FleetVehicleAllocationData{r.vehicle_ids[i], {}, 0.0});
      continue;
    }
    const Eigen::Vector3d over_end(end.x(), end.y(), cruise_m);
    if (!world->isSegmentValid(leg_paths.back().back(), over_end)) {
      return fail(PlanErrorCode::kUnreachable, indexed("ends", i),
                  "cannot be reached straight at the cruise altitude from over begins[" + std::to_string(i) +
                      "] (the vehicle's depot, where GMTPA returns it)");
    }
    add(over_end);
    add(end);
    // A straight climb from the begin to the first cruise vertex (and descent from the last one
    // to the end) where it is clear: the vertical climb's right-angle turn into the cruise makes
    // the spline overshoot near the ground, which the trajectory stage then repairs by slowing.
    auto straighten = [&](std::vector<Eigen::Vector3d>& path, std::size_t corner) {
      if (corner == 0 || corner + 1 >= path.size()) return;
      if (world->isSegmentValid(path[corner - 1], path[corner + 1])) path.erase(path.begin() + static_cast<long>(corner));
    };
    straighten(leg_paths.front(), 1);
    straighten(leg_paths.back(), leg_paths.back().size() - 2);
    points.push_back(end);
    order.push_back(static_cast<std::uint32_t>(nt + 1));

    PlannedRoute route;
    for (std::size_t l = 0; l < leg_paths.size(); ++l) {
      RouteLeg leg;
      leg.from_point = l;
      leg.to_point = l + 1;
      leg.path_m = leg_paths[l];  // from route point l to route point l + 1
      for (std::size_t k = (l == 0 ? 0 : 1); k < leg.path_m.size(); ++k) route.waypoints_m.push_back(leg.path_m[k]);
      route.legs.push_back(std::move(leg));
    }
    RouteOptions ro = o.route;
    ro.snapshot.reset();
    ro.trajectory_start_world_s.reset();
    if (Status built = buildRouteTrajectory(world, points, limits, ro, route); !built.ok()) {
      PlanError e = toPlanError(built.error());
      e.message = r.vehicle_ids[i] + ": " + e.message;
      e.field = indexed("vehicle_ids", i);
      return e;
    }
    {
      std::string repairs;
      for (const std::string& line : route.built.report.repairs) repairs += (repairs.empty() ? "" : "; ") + line;
      spdlog::debug("event=fleet_trajectory request={} vehicle={} duration_s={:.1f} status={} repairs=\"{}\"",
                    r.request_id, r.vehicle_ids[i], route.built.trajectory.duration_s(),
                    to_string(route.built.report.status), repairs);
    }
    out.flown.push_back(route.built.trajectory);
    TrajectoryData data;
    data.vehicle_id = r.vehicle_ids[i];
    data.visiting_order = order;
    for (const RouteLeg& leg : route.legs) {
      data.legs.push_back(LegBoundaryData{order[leg.from_point], order[leg.to_point], leg.start_s, leg.end_s});
    }
    out.trajectories.push_back(std::move(data));
    FleetVehicleAllocationData a;
    a.vehicle_id = r.vehicle_ids[i];
    for (int j : vp.tasks) a.tasks.push_back(static_cast<std::uint32_t>(j));
    out.status.allocation.push_back(std::move(a));
  }

  // Separation: every vehicle sampled once on its own clock; a delay of whole samples is an index
  // shift. Two vehicles at their speed limit close at most 2 v_max, so between samples (half an
  // interval from the nearer one) the distance drops by at most v_max * dt below the sampled one.
  const double dt = o.separation_dt_s;
  const double required_m = separation_m + limits.max_speed_mps * dt;
  const long step_samples = std::max(1L, std::lround(o.delay_step_s / dt));
  const long max_shift = std::lround(o.max_delay_s / dt);
  std::vector<std::vector<Eigen::Vector3d>> samples(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    const long n = static_cast<long>(std::ceil(out.flown[i].duration_s() / dt)) + 1;
    samples[i].reserve(static_cast<std::size_t>(n));
    for (long k = 0; k < n; ++k) {
      samples[i].push_back(out.flown[i].evaluate(std::min(k * dt, out.flown[i].duration_s()), Derivative::kPosition));
    }
  }
  std::vector<long> shift(nv, 0);
  auto at = [&](std::size_t i, long g) {  // position at global sample g
    const long k = g - shift[i];
    if (k <= 0) return samples[i].front();
    if (k >= static_cast<long>(samples[i].size())) return samples[i].back();
    return samples[i][static_cast<std::size_t>(k)];
  };
  auto horizon = [&](std::size_t i) { return shift[i] + static_cast<long>(samples[i].size()); };
  // The first global sample at which vehicle i comes within `required` of an earlier vehicle.
  auto firstConflict = [&](std::size_t i, double& closest_m) -> std::optional<long> {
    closest_m = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < i; ++k) {
      const long last = std::max(horizon(i), horizon(k));
      for (long g = 0; g <= last; ++g) {
        const double d = (at(i, g) - at(k, g)).norm();
        closest_m = std::min(closest_m, d);
        if (d < required_m) return g;
      }
    }
    return std::nullopt;
  };
  for (std::size_t i = 1; i < nv; ++i) {
    double closest = 0.0;
    while (firstConflict(i, closest)) {
      if (stop.shouldStop()) return fail(PlanErrorCode::kCancelled, "", "stopped during the separation repair");
      shift[i] += step_samples;
      if (shift[i] > max_shift) {
        return fail(PlanErrorCode::kUnreachable, indexed("vehicle_ids", i),
                    r.vehicle_ids[i] + " cannot keep " + std::to_string(static_cast<int>(separation_m)) +
                        " m from the vehicles before it within a delay of " + std::to_string(static_cast<int>(o.max_delay_s)) +
                        " s (its route passes too close to a point where another holds)");
      }
    }
    if (shift[i] > 0) ++out.status.separation_repairs;
  }
  // The achieved separation over the final schedule (all pairs, sampled).
  double achieved = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < nv; ++i) {
    for (std::size_t k = 0; k < i; ++k) {
      const long last = std::max(horizon(i), horizon(k));
      for (long g = 0; g <= last; ++g) achieved = std::min(achieved, (at(i, g) - at(k, g)).norm());
    }
  }
  out.status.achieved_separation_m = nv > 1 ? achieved : 0.0;

  for (std::size_t i = 0; i < nv; ++i) {
    const double delay_s = static_cast<double>(shift[i]) * dt;
    out.delays_s.push_back(delay_s);
    out.status.allocation[i].delay_s = delay_s;
    out.status.makespan_s = std::max(out.status.makespan_s, delay_s + out.flown[i].duration_s());
    TrajectoryData& d = out.trajectories[i];
    TrajectoryIdentity id{r.vehicle_ids[i], r.request_id + "-" + r.vehicle_ids[i], 0, r.request_id};
    TrajectoryData sampled = toTrajectoryData(out.flown[i], frame, o.sample_dt_s,
                                              start_utc_ns + static_cast<std::int64_t>(std::llround(delay_s * 1e9)), id);
    sampled.visiting_order = std::move(d.visiting_order);
    sampled.legs = std::move(d.legs);
    d = std::move(sampled);
  }
  return std::nullopt;
}

}  // namespace

FleetPlanOutput planFleetMission(const FleetRequestData& request, WorldModel& world, const FleetMissionOptions& options,
                                 std::int64_t start_utc_ns, const TerminationCondition& stop) {
  const auto started = std::chrono::steady_clock::now();
  FleetPlanOutput out;
  out.status.request_id = request.request_id;
  std::optional<PlanError> error = planInto(request, world, options, start_utc_ns, stop, out);
  out.status.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (error) {
    out.status.state = error->code == PlanErrorCode::kCancelled ? PlanState::kCancelled : PlanState::kFailed;
    out.status.error_code = error->code;
    out.status.field = error->field;
    out.status.message = error->describe();
    out.trajectories.clear();
  } else {
    out.status.state = PlanState::kSucceeded;
  }
  return out;
}

}  // namespace skyroute
