#include "service/fleet_replanner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>

#include <spdlog/spdlog.h>

#include "planning/grid/space_time_astar.hpp"
#include "service/fleet_step_aside.hpp"
#include "service/fleet_vehicle_route.hpp"
#include "service/route_planner.hpp"
#include "service/trajectory_data.hpp"
#include "trajectory/trajectory_splice.hpp"

namespace skyroute {

namespace {

Segment holdSegment(const Eigen::Vector3d& p, double duration_s) {
  Segment hold;
  hold.duration_s = duration_s;
  for (int axis = 0; axis < 3; ++axis) {
    Polynomial7::Coefficients c{};
    c[0] = p[axis];
    hold.axes[static_cast<std::size_t>(axis)] = Polynomial7(c);
  }
  return hold;
}

Eigen::Vector3d positionOn(const Trajectory& t, double start_s, double world_s) {
  return t.evaluate(std::clamp(world_s - start_s, 0.0, t.duration_s()), Derivative::kPosition);
}

// The part of `t` (started at start_s) from world time from_s on, and its delay after from_s:
// a vehicle before its start holds at its first point, after its end at its last.
std::pair<Trajectory, double> cutFrom(const Trajectory& t, double start_s, double from_s) {
  if (from_s <= start_s) return {t, start_s - from_s};
  if (from_s >= start_s + t.duration_s()) return {Trajectory({holdSegment(positionOn(t, start_s, from_s), 0.1)}), 0.0};
  return {Trajectory(segmentsBetween(t, from_s - start_s, t.duration_s())), 0.0};
}

// A polyline point of a candidate's route: its horizontal position and what it is (a task's
// index, kDepot, or kPlain for a cell the route turns at).
constexpr int kPlain = -1;
constexpr int kDepot = -2;
struct RoutePoint2 {
  Eigen::Vector2d xy;
  int what = kPlain;
};

// Waits (the same position twice) and straight runs collapse; tasks and the depot always stay.
std::vector<RoutePoint2> collapse(const std::vector<RoutePoint2>& in) {
  std::vector<RoutePoint2> out;
  for (const RoutePoint2& p : in) {
    if (!out.empty() && (out.back().xy - p.xy).norm() < 1e-6) {
      if (out.back().what == kPlain) out.back().what = p.what;
      else if (p.what != kPlain) out.push_back(p);  // two tasks at one place: one overflight each
      continue;
    }
    if (out.size() >= 2 && out.back().what == kPlain) {
      const Eigen::Vector2d d1 = out.back().xy - out[out.size() - 2].xy;
      const Eigen::Vector2d d2 = p.xy - out.back().xy;
      if (std::abs(d1.x() * d2.y() - d1.y() * d2.x()) < 1e-6 * d1.norm() * d2.norm() && d1.dot(d2) > 0.0) {
        out.back() = {p.xy, kPlain};
        out.back().what = p.what;
        continue;
      }
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace

std::nullopt_t FleetReplanner::rejected(std::size_t i, double wait_s, const char* why) const {
  spdlog::debug("event=fleet_candidate vehicle={} wait_s={:.0f} rejected=\"{}\"", request_.vehicle_ids[i], wait_s, why);
  return std::nullopt;
}

struct FleetReplanner::Candidate {
  Trajectory trajectory;             // from now on (the kept part first)
  double start_world_s = 0.0;
  double kept_until_s = 0.0;         // world time the kept curve of the trajectory in force ends
  std::vector<std::uint32_t> tasks;  // remaining, in order
  std::vector<double> task_times_world_s;
  std::vector<LegBoundaryData> legs;  // the new part's legs, trajectory times
  std::vector<std::uint32_t> order;
};

Result<std::unique_ptr<FleetReplanner>> FleetReplanner::create(const FleetRequestData& request,
                                                                const FleetPlanOutput& plan,
                                                                std::shared_ptr<WorldModel> world,
                                                                const FleetMissionOptions& mission_options,
                                                                const FleetReplanOptions& options, double start_world_s) {
  if (!plan.ok() || !plan.grid || plan.grid_paths.size() != request.vehicle_ids.size() ||
      plan.flown.size() != request.vehicle_ids.size()) {
    return Error{ErrorCode::kInvalidArgument, "plan", "not a successful fleet plan with its grid"};
  }
  if (!(options.lead_s >= 0.0) || !(options.check_dt_s > 0.0) || !(options.margin_m >= 0.0) ||
      !(options.budget_s > 0.0)) {
    return Error{ErrorCode::kInvalidArgument, "fleet.replan", "lead, check step, margin or budget out of range"};
  }
  auto w = world->worldFor(request.limits.min_clearance_agl_m, request.limits.ceiling_amsl_m);
  if (!w.ok()) return w.error();
  std::unique_ptr<FleetReplanner> r(new FleetReplanner());
  r->request_ = request;
  r->world_model_ = std::move(world);
  r->world_ = *w;
  r->grid_ = plan.grid;
  r->mission_options_ = mission_options;
  r->options_ = options;
  r->limits_ = toVehicleLimits(request.limits);
  r->begins_m_ = plan.begins_m;
  r->tasks_m_ = plan.tasks_m;
  r->ends_m_ = plan.ends_m;
  r->delays_s_ = plan.delays_s;
  r->start_world_s_ = start_world_s;
  r->separation_m_ = plan.status.min_separation_m;
  r->cruise_m_ = plan.cruise_altitude_m;
  r->plan_cell_m_ = plan.cell_size_m;
  r->step_s_ = plan.cell_size_m / std::max(1e-3, r->limits_.v_ref_mps);
  r->makespan_steps_ = plan.status.makespan_steps;
  for (std::size_t i = 0; i < plan.flown.size(); ++i) {
    FleetVehicleFlight v;
    v.trajectory = plan.flown[i];
    v.start_world_s = start_world_s + plan.delays_s[i];
    v.data = plan.trajectories[i];
    const TrajectoryData& d = plan.trajectories[i];
    for (const LegBoundaryData& leg : d.legs) {
      if (leg.to_point >= 1 && leg.to_point <= request.tasks.size()) {
        v.tasks.push_back(leg.to_point - 1);
        v.task_times_world_s.push_back(v.start_world_s + leg.end_s);
      }
    }
    r->vehicles_.push_back(std::move(v));
  }
  return r;
}

Eigen::Vector3d FleetReplanner::positionAt(std::size_t i, double world_s) const {
  return positionOn(vehicles_[i].trajectory, vehicles_[i].start_world_s, world_s);
}

bool FleetReplanner::finished(double now_s) const {
  if (!pending_.empty()) return false;
  for (const FleetVehicleFlight& v : vehicles_) {
    if (now_s < v.start_world_s + v.trajectory.duration_s()) return false;
  }
  return true;
}

std::optional<double> FleetReplanner::obstacleHit(const Trajectory& t, double start_s, double from_s) const {
  const std::vector<Obstacle> obstacles = world_->obstacles();
  if (obstacles.empty()) return std::nullopt;
  const double room_m = world_->options().vehicle_radius_m + options_.margin_m;
  const double end_s = start_s + t.duration_s();
  for (double s = std::max(from_s, start_s);; s += options_.check_dt_s) {
    const double at = std::min(s, end_s);
    const Eigen::Vector3d p = positionOn(t, start_s, at);
    for (const Obstacle& o : obstacles) {
      if ((p - o.centerAt(at)).norm() > o.boundingRadius() + room_m) continue;
      if (o.contains(p, at, room_m)) return at;
    }
    if (at >= end_s) break;
  }
  return std::nullopt;
}

bool FleetReplanner::anyAffected(double now_s) const {
  for (const FleetVehicleFlight& v : vehicles_) {
    if (obstacleHit(v.trajectory, v.start_world_s, now_s)) return true;
  }
  return false;
}

bool FleetReplanner::separatedFromOthers(std::size_t i, const Trajectory& t, double start_s, double from_s) const {
  SeparationCheckOptions so;
  so.separation_m = separation_m_;
  so.sample_dt_s = mission_options_.separation_dt_s;
  so.min_interval_s = mission_options_.separation_min_interval_s;
  auto mine = cutFrom(t, start_s, from_s);
  for (std::size_t k = 0; k < vehicles_.size(); ++k) {
    if (k == i) continue;
    auto other = cutFrom(vehicles_[k].trajectory, vehicles_[k].start_world_s, from_s);
    const SeparationVerdict v =
        checkFleetSeparation({mine.first, other.first}, {mine.second, other.second}, so);
    if (!v.clear) return false;
  }
  return true;
}

std::vector<std::uint32_t> FleetReplanner::remainingTasks(std::size_t i, double world_s) const {
  std::vector<std::uint32_t> left;
  const FleetVehicleFlight& v = vehicles_[i];
  for (std::size_t k = 0; k < v.tasks.size(); ++k) {
    if (v.task_times_world_s[k] > world_s) left.push_back(v.tasks[k]);
  }
  return left;
}

bool FleetReplanner::taskCovered(std::uint32_t task, double from_s, double to_s) const {
  const Eigen::Vector3d p(tasks_m_[task].x(), tasks_m_[task].y(), cruise_m_);
  const double room_m = world_->options().vehicle_radius_m + options_.margin_m;
  for (const Obstacle& o : world_->obstacles()) {
    for (double s = from_s; s <= to_s; s += options_.check_dt_s * 4.0) {
      if (o.contains(p, s, room_m)) return true;
    }
  }
  return false;
}

std::optional<Trajectory> FleetReplanner::restToRest(const std::vector<Eigen::Vector3d>& path_m,
                                                     double start_world_s) const {
  PlannedRoute route;
  RouteLeg leg;
  leg.from_point = 0;
  leg.to_point = 1;
  leg.path_m = path_m;
  route.waypoints_m = path_m;
  route.legs.push_back(std::move(leg));
  RouteOptions ro = mission_options_.route;
  ro.snapshot.reset();
  ro.trajectory_start_world_s = start_world_s;
  ro.moving_check_horizon_s = 0.0;  // moving obstacles: the candidate's checks
  if (!buildRouteTrajectory(world_, {path_m.front(), path_m.back()}, limits_, ro, route).ok()) return std::nullopt;
  if (route.built.report.status == TrajectoryStatus::kInfeasible) return std::nullopt;
  return route.built.trajectory;
}

std::optional<FleetReplanner::Candidate> FleetReplanner::buildCandidate(std::size_t i,
                                                                         const std::vector<std::uint32_t>& tasks,
                                                                         double now_s, double takeover_s,
                                                                         double wait_s,
                                                                         const TerminationCondition& stop,
                                                                         const Escape* escape) const {
  const FleetVehicleFlight& v = vehicles_[i];
  const GridLayer& grid = *grid_;
  const double from_s = std::max(now_s, v.start_world_s);
  takeover_s = std::max(takeover_s, v.start_world_s);
  const TrajectoryState state = v.trajectory.stateAt(std::min(takeover_s - v.start_world_s, v.trajectory.duration_s()));
  const bool at_rest = state.velocity_mps.norm() < 1e-3 && state.acceleration_mps2.norm() < 1e-3;

  // The kept curve, then (waiting) a stop and a hover.
  std::vector<Segment> segments = segmentsBetween(v.trajectory, from_s - v.start_world_s, takeover_s - v.start_world_s);
  Eigen::Vector3d start_m = state.position_m;
  double new_start_s = takeover_s;
  bool from_rest = at_rest;
  // The step aside and the wait begin at rest: a stop from the takeover state unless it is.
  auto stopFirst = [&] {
    if (at_rest) return true;
    const std::optional<Segment> stop = stopSegment(state, limits_);
    if (!stop) return false;
    segments.push_back(*stop);
    new_start_s += stop->duration_s;
    start_m = stop->evaluate(stop->duration_s, Derivative::kPosition);
    return true;
  };
  if (escape) {
    // Off the obstacle's track at the altitude it is at: a stop, a step aside, a hold while the
    // obstacle goes by when asked for, then the climb to the band there.
    if (!stopFirst()) return rejected(i, wait_s, "no stop from the takeover state");
    auto append = [&](const Trajectory& t) {
      segments.insert(segments.end(), t.segments().begin(), t.segments().end());
      new_start_s += t.duration_s();
    };
    const Eigen::Vector3d aside(escape->xy.x(), escape->xy.y(), start_m.z());
    const std::optional<Trajectory> step_aside = restToRest({start_m, aside}, new_start_s);
    if (!step_aside) return rejected(i, wait_s, "no step aside");
    append(*step_aside);
    start_m = aside;
    if (escape->hold_until_s > new_start_s) {
      segments.push_back(holdSegment(start_m, escape->hold_until_s - new_start_s));
      new_start_s = escape->hold_until_s;
    }
    if (escape->land) {
      // Nothing left to serve and the end below: straight down onto it from beside the track.
      const std::optional<Trajectory> down = restToRest({start_m, ends_m_[i]}, new_start_s);
      if (!down) return rejected(i, wait_s, "no descent from the step aside");
      append(*down);
      Candidate c;
      c.trajectory = Trajectory(std::move(segments));
      c.start_world_s = from_s;
      c.kept_until_s = takeover_s;
      c.order = {0, static_cast<std::uint32_t>(request_.tasks.size() + 1)};
      c.legs.push_back(LegBoundaryData{0, c.order.back(), 0.0, c.trajectory.duration_s()});
      return c;
    }
    if (start_m.z() < cruise_m_ - 1.0) {
      const Eigen::Vector3d top(start_m.x(), start_m.y(), cruise_m_);
      const std::optional<Trajectory> climb = restToRest({start_m, top}, new_start_s);
      if (!climb) return rejected(i, wait_s, "no climb from the step aside");
      append(*climb);
      start_m = top;
    }
    from_rest = true;
  } else if (wait_s > 0.0) {
    if (!stopFirst()) return rejected(i, wait_s, "no stop from the takeover state");
    segments.push_back(holdSegment(start_m, wait_s));
    new_start_s += wait_s;
    from_rest = true;
  }

  // The space-time search: other vehicles and obstacles hold cells from the new start on.
  const auto start_cell = grid.cellAt(start_m.head<2>());
  if (!start_cell) return rejected(i, wait_s, "off the grid");
  const int n = static_cast<int>(vehicles_.size());
  double last_end_s = new_start_s;
  for (const FleetVehicleFlight& o : vehicles_) last_end_s = std::max(last_end_s, o.start_world_s + o.trajectory.duration_s());
  const int horizon = static_cast<int>(std::ceil((last_end_s - new_start_s) / step_s_)) + 64;
  CellTimeReservations reservations(grid);
  const double cell = grid.cellSize();
  // Cells whose centre, at the cruise altitude, lies within radius_m of the stretch a -> b.
  auto reserveAround = [&](int agent, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius_m, int step) {
    const int reach = static_cast<int>(std::ceil(radius_m / cell)) + 1;
    const auto ca = grid.cellAt(a.head<2>());
    const auto cb = grid.cellAt(b.head<2>());
    if (!ca && !cb) return;
    const GridCell lo{std::min(ca ? ca->x : cb->x, cb ? cb->x : ca->x) - reach,
                      std::min(ca ? ca->y : cb->y, cb ? cb->y : ca->y) - reach};
    const GridCell hi{std::max(ca ? ca->x : cb->x, cb ? cb->x : ca->x) + reach,
                      std::max(ca ? ca->y : cb->y, cb ? cb->y : ca->y) + reach};
    const Eigen::Vector3d d = b - a;
    const double dd = d.squaredNorm();
    for (int y = std::max(0, lo.y); y <= std::min(grid.height() - 1, hi.y); ++y) {
      for (int x = std::max(0, lo.x); x <= std::min(grid.width() - 1, hi.x); ++x) {
        const Eigen::Vector2d centre = grid.cellCenter(GridCell{x, y});
        const Eigen::Vector3d q(centre.x(), centre.y(), cruise_m_);
        const double w = dd > 0.0 ? std::clamp((q - a).dot(d) / dd, 0.0, 1.0) : 0.0;
        if ((a + w * d - q).norm() < radius_m) reservations.reserveCellAt(agent, GridCell{x, y}, step);
      }
    }
  };
  const double vehicle_room_m = separation_m_ + 0.75 * cell;
  for (int k = 0; k < n; ++k) {
    if (k == static_cast<int>(i)) continue;
    for (int s = 0; s <= horizon; ++s) {
      const Eigen::Vector3d p = positionAt(static_cast<std::size_t>(k), new_start_s + s * step_s_);
      reserveAround(k, p, p, vehicle_room_m, s);
    }
  }
  const std::vector<Obstacle> obstacles = world_->obstacles();
  const double obstacle_room_m = world_->options().vehicle_radius_m + options_.margin_m + 0.75 * cell;
  for (std::size_t k = 0; k < obstacles.size(); ++k) {
    const Obstacle& o = obstacles[k];
    const int agent = n + static_cast<int>(k);
    // On the band the obstacle's horizontal extent counts (a column's height does not).
    const double extent_m = horizontalReachM(o);
    for (int s = 0; s <= horizon; ++s) {  // the stretch it covers round each step
      const Eigen::Vector3d a = o.centerAt(new_start_s + (s - 0.5) * step_s_);
      const Eigen::Vector3d b = o.centerAt(new_start_s + (s + 0.5) * step_s_);
      Eigen::Vector3d a_band = a, b_band = b;
      a_band.z() = b_band.z() = cruise_m_;  // vertical reach checked once below
      const double vertical_m = verticalReachM(o);
      if (std::abs(a.z() - cruise_m_) > vertical_m + obstacle_room_m && std::abs(b.z() - cruise_m_) > vertical_m + obstacle_room_m) continue;
      reserveAround(agent, a_band, b_band, extent_m + obstacle_room_m, s);
    }
  }
  // A task under an obstacle that does not move stays covered for as long as the world knows.
  const double room_m = world_->options().vehicle_radius_m + options_.margin_m;
  for (std::uint32_t j : tasks) {
    const Eigen::Vector3d over(tasks_m_[j].x(), tasks_m_[j].y(), cruise_m_);
    for (const Obstacle& o : obstacles) {
      if (!o.moving() && o.contains(over, new_start_s, room_m)) return rejected(i, wait_s, "a task under a fixed obstacle");
    }
  }
  std::vector<GridCell> goals;
  for (std::uint32_t j : tasks) goals.push_back(*grid.cellAt(tasks_m_[j].head<2>()));
  goals.push_back(*grid.cellAt(begins_m_[i].head<2>()));
  std::vector<RoutePoint2> polyline{{start_m.head<2>(), kPlain}};
  GridCell at = *start_cell;
  int step = 0;
  for (std::size_t g = 0; g < goals.size(); ++g) {
    const int what = g < tasks.size() ? static_cast<int>(tasks[g]) : kDepot;
    const Eigen::Vector2d goal_xy = g < tasks.size() ? tasks_m_[tasks[g]].head<2>() : begins_m_[i].head<2>();
    if (at == goals[g]) {
      polyline.push_back({goal_xy, what});
      continue;
    }
    SpaceTimeQuery q;
    q.self = static_cast<int>(i);
    q.start = at;
    q.start_step = step;
    q.goal = goals[g];
    q.park_at_goal = false;
    q.max_expansions = options_.max_expansions;
    const SpaceTimePath path = planSpaceTime(grid, reservations, q, stop);
    if (!path.found()) return rejected(i, wait_s, "no space-time path");
    for (std::size_t c = 1; c + 1 < path.cells.size(); ++c) polyline.push_back({grid.cellCenter(path.cells[c]), kPlain});
    polyline.push_back({goal_xy, what});
    at = goals[g];
    step = path.arrivalStep();
  }
  const std::vector<RoutePoint2> kept = collapse(polyline);

  // Lifted to the cruise altitude: a route point at each task, legs between them.
  std::vector<Eigen::Vector3d> points{start_m};
  std::vector<std::vector<Eigen::Vector3d>> leg_paths{{start_m}};
  std::vector<std::uint32_t> order{0};
  auto add = [&](const Eigen::Vector3d& p) {
    if ((leg_paths.back().back() - p).norm() > 1e-3) leg_paths.back().push_back(p);
  };
  if (start_m.z() < cruise_m_ - 1.0) add(Eigen::Vector3d(start_m.x(), start_m.y(), cruise_m_));
  for (std::size_t k = 1; k < kept.size(); ++k) {
    const Eigen::Vector3d p(kept[k].xy.x(), kept[k].xy.y(), cruise_m_);
    add(p);
    if (kept[k].what >= 0) {
      points.push_back(p);
      order.push_back(static_cast<std::uint32_t>(kept[k].what) + 1);
      leg_paths.push_back({p});
    }
  }
  const Eigen::Vector3d& end = ends_m_[i];
  const Eigen::Vector3d over_end(end.x(), end.y(), cruise_m_);
  if (!world_->isStaticSegmentValid(leg_paths.back().back(), over_end)) return rejected(i, wait_s, "the way to over the end is blocked");
  add(over_end);
  add(end);
  points.push_back(end);
  order.push_back(static_cast<std::uint32_t>(request_.tasks.size() + 1));
  if (points.size() != tasks.size() + 2) return rejected(i, wait_s, "a task folded into another point");  // a task folded into another point

  PlannedRoute route;
  for (std::size_t l = 0; l < leg_paths.size(); ++l) {
    if (leg_paths[l].size() < 2) return rejected(i, wait_s, "an empty leg");
    RouteLeg leg;
    leg.from_point = l;
    leg.to_point = l + 1;
    leg.path_m = leg_paths[l];
    for (std::size_t k = (l == 0 ? 0 : 1); k < leg.path_m.size(); ++k) route.waypoints_m.push_back(leg.path_m[k]);
    route.legs.push_back(std::move(leg));
  }
  RouteOptions ro = mission_options_.route;
  ro.snapshot.reset();
  ro.trajectory_start_world_s = new_start_s;
  ro.moving_check_horizon_s = 0.0;  // moving obstacles: the checks below, over the whole flight
  if (!from_rest) {
    ro.trajectory.time_allocation.accel_fraction = std::min(ro.trajectory.time_allocation.accel_fraction, 0.5);
    ro.trajectory.boundary.start.velocity_mps = state.velocity_mps;
    ro.trajectory.boundary.start.acceleration_mps2 = state.acceleration_mps2;
    ro.trajectory.boundary.start.jerk_mps3 = state.jerk_mps3;
  }
  if (!buildRouteTrajectory(world_, points, limits_, ro, route).ok()) return rejected(i, wait_s, "the trajectory stage failed");
  if (route.built.report.status == TrajectoryStatus::kInfeasible) return rejected(i, wait_s, "the trajectory is infeasible");

  Candidate c;
  double kept_s = 0.0;
  for (const Segment& s : segments) kept_s += s.duration_s;
  const std::vector<Segment>& planned = route.built.trajectory.segments();
  segments.insert(segments.end(), planned.begin(), planned.end());
  c.trajectory = Trajectory(std::move(segments));
  c.start_world_s = from_s;
  c.kept_until_s = takeover_s;
  c.tasks = tasks;
  c.order = order;
  for (const RouteLeg& leg : route.legs) {
    c.legs.push_back(LegBoundaryData{order[leg.from_point], order[leg.to_point], kept_s + leg.start_s, kept_s + leg.end_s});
    if (leg.to_point + 1 < points.size()) c.task_times_world_s.push_back(new_start_s + leg.end_s);
  }
  if (!c.legs.empty()) c.legs.front().start_s = 0.0;
  return c;
}

std::optional<FleetReplanner::Candidate> FleetReplanner::replanVehicle(std::size_t i,
                                                                        const std::vector<std::uint32_t>& tasks,
                                                                        double now_s, const TerminationCondition& stop,
                                                                        std::size_t& built) const {
  const double takeover_s = now_s + options_.lead_s;
  std::vector<double> waits{0.0};
  waits.insert(waits.end(), options_.waits_s.begin(), options_.waits_s.end());
  auto passes = [&](const std::optional<Candidate>& c, double wait_s) {
    if (!c) return false;
    if (auto hit = obstacleHit(c->trajectory, c->start_world_s, c->start_world_s)) {
      spdlog::debug("event=fleet_candidate vehicle={} wait_s={:.0f} rejected=\"meets an obstacle {:.1f} s ahead\"",
                    request_.vehicle_ids[i], wait_s, *hit - now_s);
      return false;
    }
    if (!separatedFromOthers(i, c->trajectory, c->start_world_s, c->start_world_s)) {
      spdlog::debug("event=fleet_candidate vehicle={} wait_s={:.0f} rejected=\"too close to another vehicle\"",
                    request_.vehicle_ids[i], wait_s);
      return false;
    }
    // Last, the audit's own check of the whole revision (zones at each sample's time, obstacles,
    // limits): every candidate adopted comes through here, so none refused is ever published.
    if (options_.audit && options_.audit(i, c->trajectory, c->start_world_s, now_s, vehicles_[i].revision + 1)) {
      rejected(i, wait_s, "the audit refused it");
      return false;
    }
    return true;
  };
  for (double wait_s : waits) {
    if (stop.shouldStop()) return std::nullopt;
    std::optional<Candidate> c = buildCandidate(i, tasks, now_s, takeover_s, wait_s, stop);
    ++built;
    if (passes(c, wait_s)) return c;
    if (wait_s > 0.0) continue;
    // Below the band at the takeover (climbing over its begin, descending onto its end, or not
    // yet launched): a hover stays on the track of an obstacle that reaches every altitude it
    // passes through, so it steps off that track first.
    const FleetVehicleFlight& v = vehicles_[i];
    const double at_s = std::clamp(takeover_s, v.start_world_s, v.start_world_s + v.trajectory.duration_s());
    const Eigen::Vector3d p = positionAt(i, at_s);
    if (p.z() >= cruise_m_ - 1.0) continue;
    // With nothing left to serve over its end, it lands from beside the track rather than
    // climbing back to the band.
    const bool land = tasks.empty() && (p.head<2>() - ends_m_[i].head<2>()).norm() < plan_cell_m_;
    // Beyond the obstacle's reach by the room the checks keep and a grid cell (the band search
    // blocks the cells round the obstacle's track by most of a cell more).
    const double room_m = world_->options().vehicle_radius_m + options_.margin_m + plan_cell_m_;
    for (const StepAside& aside : stepAsidesFrom(world_->obstacles(), p, cruise_m_, room_m, at_s)) {
      if (stop.shouldStop()) return std::nullopt;
      const Escape escape{aside.xy, aside.hold_until_s, land};
      std::optional<Candidate> e = buildCandidate(i, tasks, now_s, takeover_s, 0.0, stop, &escape);
      ++built;
      if (passes(e, escape.hold_until_s > 0.0 ? escape.hold_until_s - now_s : 0.0)) return e;
    }
  }
  return std::nullopt;
}

void FleetReplanner::adopt(std::size_t i, Candidate c) {
  FleetVehicleFlight& v = vehicles_[i];
  // Tasks served before the takeover stay with their times; those on the kept curve (after the
  // new revision starts) are legs of the new revision too.
  std::vector<std::uint32_t> tasks;
  std::vector<double> times;
  std::vector<std::uint32_t> order{0};
  std::vector<LegBoundaryData> legs;
  double leg_start_s = 0.0;
  for (std::size_t k = 0; k < v.tasks.size(); ++k) {
    const double at = v.task_times_world_s[k];
    if (at > c.kept_until_s) continue;
    tasks.push_back(v.tasks[k]);
    times.push_back(at);
    if (at > c.start_world_s) {
      legs.push_back(LegBoundaryData{order.back(), v.tasks[k] + 1, leg_start_s, at - c.start_world_s});
      order.push_back(v.tasks[k] + 1);
      leg_start_s = at - c.start_world_s;
    }
  }
  if (!c.legs.empty()) {
    c.legs.front().from_point = order.back();
    c.legs.front().start_s = leg_start_s;
  }
  order.insert(order.end(), c.order.begin() + 1, c.order.end());
  legs.insert(legs.end(), c.legs.begin(), c.legs.end());
  tasks.insert(tasks.end(), c.tasks.begin(), c.tasks.end());
  times.insert(times.end(), c.task_times_world_s.begin(), c.task_times_world_s.end());
  v.tasks = std::move(tasks);
  v.task_times_world_s = std::move(times);
  v.trajectory = std::move(c.trajectory);
  v.start_world_s = c.start_world_s;
  ++v.revision;
  const TrajectoryIdentity id{request_.vehicle_ids[i], v.data.plan_id, v.revision, request_.request_id};
  TrajectoryData data = toTrajectoryData(v.trajectory, world_model_->frame(), mission_options_.sample_dt_s,
                                         static_cast<std::int64_t>(std::llround(v.start_world_s * 1e9)), id);
  data.visiting_order = std::move(order);
  data.legs = std::move(legs);
  v.data = std::move(data);
}

FleetReplanStep FleetReplanner::step(double now_s, const TerminationCondition& outer) {
  const auto started = std::chrono::steady_clock::now();
  FleetReplanStep out;
  TerminationCondition stop =
      TerminationCondition::after(std::chrono::nanoseconds(static_cast<std::int64_t>(options_.budget_s * 1e9)));
  if (outer.sharedCancelFlag()) stop.withCancelFlag(outer.sharedCancelFlag());
  auto stopped = [&] { return outer.shouldStop() || stop.shouldStop(); };

  for (std::size_t i = 0; i < vehicles_.size(); ++i) {
    if (obstacleHit(vehicles_[i].trajectory, vehicles_[i].start_world_s, now_s)) marked_.insert(i);
  }
  out.affected.assign(marked_.begin(), marked_.end());
  std::set<std::size_t> changed;
  const double takeover_s = now_s + options_.lead_s;
  for (std::size_t i : out.affected) {
    if (stopped()) {
      out.unfinished = true;
      break;
    }
    const std::vector<std::uint32_t> left = remainingTasks(i, takeover_s);
    std::optional<Candidate> c = replanVehicle(i, left, now_s, stop, out.candidates);
    if (!c) {
      // Tasks an obstacle covers go to the pending list first; then every remaining one.
      const double end_s = vehicles_[i].start_world_s + vehicles_[i].trajectory.duration_s() + 600.0;
      std::vector<std::uint32_t> open, covered;
      for (std::uint32_t j : left) (taskCovered(j, takeover_s, end_s) ? covered : open).push_back(j);
      if (!covered.empty()) {
        c = replanVehicle(i, open, now_s, stop, out.candidates);
        if (c) pending_.insert(covered.begin(), covered.end());
      }
      if (!c && !left.empty()) {
        c = replanVehicle(i, {}, now_s, stop, out.candidates);
        if (c) pending_.insert(left.begin(), left.end());
      }
    }
    if (stopped()) {
      out.unfinished = true;  // this vehicle again at the next step
      break;
    }
    marked_.erase(i);  // seen: replanned, or nothing passes until the world changes again
    if (c) {
      adopt(i, std::move(*c));
      changed.insert(i);
      unresolved_.erase(i);
    } else {
      unresolved_.insert(i);
    }
  }

  // Pending tasks, each offered to the vehicles still flying, cheapest insertion first.
  for (auto it = pending_.begin(); it != pending_.end() && !stopped();) {
    const std::uint32_t j = *it;
    struct Offer {
      double added_m;
      std::size_t vehicle;
      std::vector<std::uint32_t> tasks;
    };
    std::vector<Offer> offers;
    for (std::size_t k = 0; k < vehicles_.size(); ++k) {
      const FleetVehicleFlight& v = vehicles_[k];
      if (takeover_s >= v.start_world_s + v.trajectory.duration_s()) continue;  // landed
      const std::vector<std::uint32_t> left = remainingTasks(k, takeover_s);
      std::vector<Eigen::Vector2d> stops{positionAt(k, takeover_s).head<2>()};
      for (std::uint32_t t : left) stops.push_back(tasks_m_[t].head<2>());
      stops.push_back(begins_m_[k].head<2>());
      const Eigen::Vector2d p = tasks_m_[j].head<2>();
      double best = std::numeric_limits<double>::infinity();
      std::size_t at = 0;
      for (std::size_t s = 0; s + 1 < stops.size(); ++s) {
        const double added = (stops[s] - p).norm() + (p - stops[s + 1]).norm() - (stops[s] - stops[s + 1]).norm();
        if (added < best) {
          best = added;
          at = s;
        }
      }
      std::vector<std::uint32_t> tasks = left;
      tasks.insert(tasks.begin() + static_cast<long>(at), j);
      offers.push_back({best, k, std::move(tasks)});
    }
    std::sort(offers.begin(), offers.end(), [](const Offer& a, const Offer& b) {
      return a.added_m != b.added_m ? a.added_m < b.added_m : a.vehicle < b.vehicle;
    });
    bool taken = false;
    for (const Offer& offer : offers) {
      if (stopped()) break;
      std::optional<Candidate> c = replanVehicle(offer.vehicle, offer.tasks, now_s, stop, out.candidates);
      if (!c) continue;
      adopt(offer.vehicle, std::move(*c));
      changed.insert(offer.vehicle);
      out.reallocated.push_back(j);
      taken = true;
      break;
    }
    it = taken ? pending_.erase(it) : std::next(it);
  }
  if (stopped() && !marked_.empty()) out.unfinished = true;
  out.changed.assign(changed.begin(), changed.end());
  out.pending.assign(pending_.begin(), pending_.end());
  for (std::size_t i : unresolved_) {
    // Resolved meanwhile when its trajectory in force (another step's) no longer meets anything.
    if (obstacleHit(vehicles_[i].trajectory, vehicles_[i].start_world_s, now_s)) out.unresolved.push_back(i);
  }
  unresolved_ = std::set<std::size_t>(out.unresolved.begin(), out.unresolved.end());
  out.latency_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return out;
}

FleetStatusData FleetReplanner::status(double latency_s) const {
  FleetStatusData s;
  s.request_id = request_.request_id;
  s.state = PlanState::kReplanned;
  s.makespan_steps = makespan_steps_;
  s.min_separation_m = separation_m_;
  // Every adopted revision was proven at least this far from every other vehicle's.
  s.achieved_separation_m = separation_m_;
  s.planning_time_s = latency_s;
  for (std::size_t i = 0; i < vehicles_.size(); ++i) {
    const FleetVehicleFlight& v = vehicles_[i];
    FleetVehicleAllocationData a;
    a.vehicle_id = request_.vehicle_ids[i];
    a.tasks = v.tasks;
    a.delay_s = delays_s_[i];
    s.allocation.push_back(std::move(a));
    s.makespan_s = std::max(s.makespan_s, v.start_world_s + v.trajectory.duration_s() - start_world_s_);
  }
  if (!unresolved_.empty()) {
    const std::size_t i = *unresolved_.begin();
    s.error_code = PlanErrorCode::kUnreachable;
    s.field = "vehicle_ids[" + std::to_string(i) + "]";
    s.message = s.field + ": " + request_.vehicle_ids[i] +
                " meets an obstacle and no revision clear of it and of the other vehicles was found (neither a "
                "detour on the flight band, a hover, nor a step aside off the obstacle's track below the band); its "
                "revision in force stays";
  } else if (!pending_.empty()) {
    s.error_code = PlanErrorCode::kUnreachable;
    s.field = "tasks[" + std::to_string(*pending_.begin()) + "]";
    s.message = s.field + ": " + std::to_string(pending_.size()) +
                " task(s) no vehicle can reach now (an obstacle covers them); offered again when the obstacles change";
  }
  return s;
}

}  // namespace skyroute
