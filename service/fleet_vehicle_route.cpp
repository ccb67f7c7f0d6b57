#include "service/fleet_vehicle_route.hpp"

#include <cmath>
#include <cstdint>
#include <utility>

#include <spdlog/spdlog.h>

namespace skyroute {

namespace {

PlanError fail(PlanErrorCode code, std::string field, std::string message) {
  return PlanError{code, std::move(field), std::move(message)};
}

bool nearlyEqual2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return (a - b).norm() < 1e-6; }

// A route across the grid, one entry per point: its horizontal position, its route point id (0 =
// begin, j + 1 = task j, -1 = a plain cell) and the grid cell it belongs to.
struct GridRoute {
  std::vector<Eigen::Vector2d> xy;
  std::vector<int> route_point;
  std::vector<GridCell> cell;
};

// The horizontal route: begin, the cells (a task's own position at its step), begin again.
std::optional<GridRoute> routeOverCells(const VehiclePlan& vp, const std::vector<Eigen::Vector3d>& tasks_m,
                                        const Eigen::Vector3d& begin, const GridLayer& grid) {
  GridRoute route{{begin.head<2>()}, {0}, {vp.cells.front()}};
  std::size_t next_task = 0;
  for (int t = 1; t <= vp.finish_step && t < static_cast<int>(vp.cells.size()); ++t) {
    const GridCell c = vp.cells[static_cast<std::size_t>(t)];
    route.cell.push_back(c);
    if (next_task < vp.tasks.size() && vp.task_steps[next_task] == t) {
      route.xy.push_back(tasks_m[static_cast<std::size_t>(vp.tasks[next_task])].head<2>());
      route.route_point.push_back(vp.tasks[next_task] + 1);
      ++next_task;
    } else {
      route.xy.push_back(t == vp.finish_step ? Eigen::Vector2d(begin.head<2>()) : grid.cellCenter(c));
      route.route_point.push_back(-1);
    }
  }
  if (next_task != vp.tasks.size()) return std::nullopt;  // task steps out of order
  return route;
}

// Waits and straight runs collapse: within one cell the route point (begin, task) stands for the
// cell, and a plain cell is kept only where the route turns. The result has no cells.
GridRoute collapseRoute(const GridRoute& in) {
  GridRoute kept;
  GridCell last_cell{-1, -1};
  for (std::size_t k = 0; k < in.xy.size(); ++k) {
    const bool same_cell = !kept.xy.empty() && in.cell[k] == last_cell;
    last_cell = in.cell[k];
    if (same_cell && in.route_point[k] < 0) continue;
    if (same_cell && kept.route_point.back() < 0) {
      kept.xy.back() = in.xy[k];
      kept.route_point.back() = in.route_point[k];
      continue;
    }
    if (same_cell && nearlyEqual2(kept.xy.back(), in.xy[k])) {
      continue;  // two tasks at one position: one overflight does both (the second is not a new leg)
    }
    if (kept.xy.size() >= 2 && kept.route_point.back() < 0 && in.route_point[k] < 0) {
      const Eigen::Vector2d a = kept.xy[kept.xy.size() - 2];
      const Eigen::Vector2d b = kept.xy.back();
      const Eigen::Vector2d d1 = b - a;
      const Eigen::Vector2d d2 = in.xy[k] - b;
      if (std::abs(d1.x() * d2.y() - d1.y() * d2.x()) < 1e-6 * d1.norm() * d2.norm() && d1.dot(d2) > 0.0) {
        kept.xy.back() = in.xy[k];  // b lies on the straight line from a to here
        continue;
      }
    }
    kept.xy.push_back(in.xy[k]);
    kept.route_point.push_back(in.route_point[k]);
  }
  return kept;
}

// An idle vehicle (no tasks, home already) stays where it is: a constant trajectory of one sample
// interval rather than a climb to the cruise altitude and back.
void addHold(const FleetRouteContext& context, std::size_t i, const Eigen::Vector3d& begin, FleetPlanOutput& out) {
  const double sample_dt_s = context.options.sample_dt_s;
  const auto end_point = static_cast<std::uint32_t>(context.request.tasks.size() + 1);
  Segment hold;
  hold.duration_s = sample_dt_s;
  for (int axis = 0; axis < 3; ++axis) {
    Polynomial7::Coefficients c{};
    c[0] = begin[axis];
    hold.axes[static_cast<std::size_t>(axis)] = Polynomial7(c);
  }
  out.flown.emplace_back(std::vector<Segment>{hold});
  TrajectoryData data;
  data.vehicle_id = context.request.vehicle_ids[i];
  data.visiting_order = {0, end_point};
  data.legs.push_back(LegBoundaryData{0, end_point, 0.0, sample_dt_s});
  out.trajectories.push_back(std::move(data));
  out.status.allocation.push_back(FleetVehicleAllocationData{context.request.vehicle_ids[i], {}, 0.0});
}

// The route points (begin, tasks at cruise, end) with the legs' 3D paths between them, in
// visiting order.
struct LiftedRoute {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::vector<Eigen::Vector3d>> leg_paths;
  std::vector<std::uint32_t> order;
};

// Lift: climb over the begin, cruise, fly on to over the end, descend.
std::optional<PlanError> liftRoute(const FleetRouteContext& context, std::size_t i, const GridRoute& kept,
                                   const Eigen::Vector3d& begin, const Eigen::Vector3d& end, LiftedRoute& lifted) {
  const double cruise_m = context.cruise_m;
  lifted.points = {begin};
  lifted.leg_paths.assign(1, std::vector<Eigen::Vector3d>{begin});
  lifted.order = {0};
  auto add = [&](const Eigen::Vector3d& p) {
    if ((lifted.leg_paths.back().back() - p).norm() > 1e-6) lifted.leg_paths.back().push_back(p);
  };
  add(Eigen::Vector3d(begin.x(), begin.y(), cruise_m));
  for (std::size_t k = 1; k < kept.xy.size(); ++k) {
    const Eigen::Vector3d p(kept.xy[k].x(), kept.xy[k].y(), cruise_m);
    add(p);
    if (kept.route_point[k] > 0) {  // a task: a route point, and a new leg starts there
      lifted.points.push_back(p);
      lifted.order.push_back(static_cast<std::uint32_t>(kept.route_point[k]));
      lifted.leg_paths.push_back({p});
    }
  }
  const Eigen::Vector3d over_end(end.x(), end.y(), cruise_m);
  if (!context.world->isSegmentValid(lifted.leg_paths.back().back(), over_end)) {
    return fail(PlanErrorCode::kUnreachable, indexedField("ends", i),
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
    if (context.world->isSegmentValid(path[corner - 1], path[corner + 1]))
      path.erase(path.begin() + static_cast<long>(corner));
  };
  straighten(lifted.leg_paths.front(), 1);
  straighten(lifted.leg_paths.back(), lifted.leg_paths.back().size() - 2);
  lifted.points.push_back(end);
  lifted.order.push_back(static_cast<std::uint32_t>(context.request.tasks.size() + 1));
  return std::nullopt;
}

// The trajectory stage over the lifted route's legs.
std::optional<PlanError> buildTrajectory(const FleetRouteContext& context, std::size_t i, const LiftedRoute& lifted,
                                         PlannedRoute& route) {
  for (std::size_t l = 0; l < lifted.leg_paths.size(); ++l) {
    RouteLeg leg;
    leg.from_point = l;
    leg.to_point = l + 1;
    leg.path_m = lifted.leg_paths[l];  // from route point l to route point l + 1
    for (std::size_t k = (l == 0 ? 0 : 1); k < leg.path_m.size(); ++k) route.waypoints_m.push_back(leg.path_m[k]);
    route.legs.push_back(std::move(leg));
  }
  RouteOptions ro = context.options.route;
  ro.snapshot.reset();
  ro.trajectory_start_world_s.reset();
  const std::string& vehicle_id = context.request.vehicle_ids[i];
  if (Status built = buildRouteTrajectory(context.world, lifted.points, context.limits, ro, route); !built.ok()) {
    PlanError e = toPlanError(built.error());
    e.message = vehicle_id + ": " + e.message;
    e.field = indexedField("vehicle_ids", i);
    return e;
  }
  std::string repairs;
  for (const std::string& line : route.built.report.repairs) repairs += (repairs.empty() ? "" : "; ") + line;
  spdlog::debug("event=fleet_trajectory request={} vehicle={} duration_s={:.1f} status={} repairs=\"{}\"",
                context.request.request_id, vehicle_id, route.built.trajectory.duration_s(),
                to_string(route.built.report.status), repairs);
  return std::nullopt;
}

}  // namespace

std::optional<PlanError> addFleetVehicleRoute(const FleetRouteContext& context, std::size_t i, const VehiclePlan& vp,
                                              FleetPlanOutput& out) {
  const Eigen::Vector3d& begin = out.begins_m[i];
  const Eigen::Vector3d& end = out.ends_m[i];
  const std::optional<GridRoute> over_cells = routeOverCells(vp, out.tasks_m, begin, context.grid);
  if (!over_cells) return fail(PlanErrorCode::kInternal, indexedField("vehicle_ids", i), "task steps out of order");
  const GridRoute kept = collapseRoute(*over_cells);
  if (vp.tasks.empty() && (end - begin).norm() < 1e-3) {
    addHold(context, i, begin, out);
    return std::nullopt;
  }
  LiftedRoute lifted;
  if (auto e = liftRoute(context, i, kept, begin, end, lifted)) return e;
  PlannedRoute route;
  if (auto e = buildTrajectory(context, i, lifted, route)) return e;

  out.flown.push_back(route.built.trajectory);
  TrajectoryData data;
  data.vehicle_id = context.request.vehicle_ids[i];
  data.visiting_order = lifted.order;
  for (const RouteLeg& leg : route.legs) {
    data.legs.push_back(
        LegBoundaryData{lifted.order[leg.from_point], lifted.order[leg.to_point], leg.start_s, leg.end_s});
  }
  out.trajectories.push_back(std::move(data));
  FleetVehicleAllocationData a;
  a.vehicle_id = context.request.vehicle_ids[i];
  for (int j : vp.tasks) a.tasks.push_back(static_cast<std::uint32_t>(j));
  out.status.allocation.push_back(std::move(a));
  return std::nullopt;
}

}  // namespace skyroute
