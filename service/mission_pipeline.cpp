#include "service/mission_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "service/mission_point_check.hpp"

namespace skyroute {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// The trajectory stage names its limits after VehicleLimits; the request after the IDL.
std::string requestLimitField(const std::string& field) {
  if (field == "limits.max_climb_mps") return "limits.max_climb_rate_mps";
  if (field == "limits.max_descent_mps") return "limits.max_descent_rate_mps";
  return field;
}

PlanError stageError(PlanErrorCode code, std::string field, std::string message, PlanStage stage,
                     int point_index = -1) {
  PlanError e{code, std::move(field), std::move(message)};
  e.stage = stage;
  e.point_index = point_index;
  return e;
}

// Which stage a route error comes from: the trajectory stage names "trajectory" or a limit.
PlanStage routeStage(const Error& e) {
  if (isTrajectoryStageError(e) || e.field.rfind("limits", 0) == 0 || e.field == "audit") return PlanStage::kTrajectory;
  return PlanStage::kLegs;
}

// Asks a shared cancel flag; for the trajectory stage's checks, which know no planning types.
std::function<bool()> stopWhen(const std::shared_ptr<std::atomic<bool>>& cancel) {
  if (!cancel) return {};
  return [cancel] { return cancel->load(); };
}

}  // namespace

std::string requestPointName(int index, int count) {
  if (index == 0) return "begin";
  if (index == count - 1) return "end";
  return "points[" + std::to_string(index - 1) + "]";
}

FleetMissionOptions fleetMissionOptions(const PipelineOptions& o) {
  FleetMissionOptions fleet = o.fleet;
  fleet.sample_dt_s = o.sample_dt_s;
  fleet.route.trajectory = o.replan.route.trajectory;
  fleet.limit_bounds = o.bounds.limits;
  fleet.trajectory_bounds = o.bounds.trajectory;
  fleet.default_model = o.vehicle.model;
  return fleet;
}

ReplanOptions PipelineOptions::defaultReplanOptions() {
  ReplanOptions o;
  o.route.leg_budget_ms = 0.0;
  o.route.leg_max_iterations = PlanBudget{}.leg_max_iterations;
  o.replan_leg_max_iterations = 400;
  return o;
}

ReplanOptions pipelineReplanOptions(const PipelineOptions& options, const PlanBudget& budget, std::uint64_t seed) {
  ReplanOptions replan = options.replan;
  replan.route.seed = seed;
  replan.route.leg_max_iterations = budget.leg_max_iterations;
  replan.route.leg_budget_ms = budget.leg_time_cap_s * 1e3;
  return replan;
}

std::optional<PlanError> validatePipelineOptions(const PipelineOptions& o) {
  auto bad = [](std::string key, std::string message) {
    return PlanError{PlanErrorCode::kInvalidArgument, std::move(key), std::move(message)};
  };
  if (auto unknown = findRoutePlanner(o.default_planner, nullptr, "planning.default_planner")) return unknown;
  if (!(o.sample_dt_s > 0.0)) return bad("planning.sample_dt_s", "must be positive");
  if (!(o.budget.leg_time_cap_s >= 0.0)) return bad("planning.leg_time_cap_s", "must be zero (none) or positive");
  if (o.budget.leg_max_iterations == 0 && o.budget.leg_time_cap_s <= 0.0) {
    return bad("planning.leg_max_iterations", "and planning.leg_time_cap_s are both 0: a leg's search would never stop");
  }
  if (!(o.replan.period_s > 0.0)) return bad("replanning.period_s", "must be positive");
  if (auto audit = validateAuditOptions(o.audit)) return bad(audit->field, audit->message);
  return std::nullopt;
}

PlanError requestPlanError(const Error& e, const std::vector<int>& order, PlanStage stage) {
  PlanError out = toPlanError(e);
  out.stage = stage;
  out.field = requestLimitField(out.field);
  const int count = static_cast<int>(order.size());
  auto index = [&](const std::string& prefix) -> std::optional<int> {
    if (e.field.rfind(prefix, 0) != 0) return std::nullopt;
    try {
      const int k = std::stoi(e.field.substr(prefix.size()));
      if (k >= 0 && k < count) return k;
    } catch (const std::exception&) {
    }
    return std::nullopt;
  };
  if (auto k = index("points[")) {
    out.field = requestPointName(order[*k], count);
    out.point_index = order[*k];
  } else if (auto leg = index("legs[")) {
    out.leg_index = *leg;
    if (*leg + 1 < count) {
      out.message += " (the leg from " + requestPointName(order[*leg], count) + " to " + requestPointName(order[*leg + 1], count) + ")";
      out.field = requestPointName(order[*leg + 1], count);
      out.point_index = order[*leg + 1];
    }
  }
  return out;
}

MissionPipeline::MissionPipeline(std::shared_ptr<WorldModel> world, PipelineOptions options)
    : world_(std::move(world)), options_(std::move(options)) {}

Result<OrderedMission, PlanError> MissionPipeline::order(const MissionRequestData& r, double start_world_s,
                                                         const TerminationCondition& stop) const {
  if (auto problem = validateMissionRequest(r, options_.bounds)) {
    PlanError e = *problem;
    e.stage = PlanStage::kValidate;
    return e;
  }
  OrderedMission out;
  const std::string planner_name = r.planner.empty() ? options_.default_planner : r.planner;
  if (auto unknown = findRoutePlanner(planner_name, &out.planner)) {
    unknown->stage = PlanStage::kValidate;
    return *unknown;
  }
  const int count = static_cast<int>(r.points.size()) + 2;
  const LocalFrame& frame = world_->frame();
  out.points_m.push_back(r.begin.toEnu(frame));
  for (const MissionPointData& p : r.points) out.points_m.push_back(p.toEnu(frame));
  out.points_m.push_back(r.end.toEnu(frame));

  auto world = world_->worldFor(r.limits.min_clearance_agl_m, r.limits.ceiling_amsl_m);
  if (!world.ok()) {
    return stageError(PlanErrorCode::kLimitsOutOfRange, world.error().field, world.error().message, PlanStage::kValidate);
  }
  out.world = *world;
  out.limits = toVehicleLimits(withVehicleDefaults(r.limits, options_.vehicle));
  if (Status ok = out.limits.validate(); !ok.ok()) {
    return stageError(PlanErrorCode::kLimitsOutOfRange, requestLimitField(ok.error().field), ok.error().message,
                      PlanStage::kValidate);
  }
  ObstacleSnapshot snapshot;
  snapshot.time_s = start_world_s;
  for (int i = 0; i < count; ++i) {
    const MissionPointData& point = i == 0 ? r.begin : i == count - 1 ? r.end : r.points[static_cast<std::size_t>(i - 1)];
    if (auto bad = checkMissionPoint(*out.world, point, requestPointName(i, count), snapshot)) {
      bad->stage = PlanStage::kValidate;
      bad->point_index = i;
      return *bad;
    }
  }
  auto ordering = orderMissionPoints(world_->terrain(), out.points_m, r.limits.min_clearance_agl_m,
                                     r.limits.ceiling_amsl_m, r.fixed_order, options_.order, stop,
                                     out.world->noFlyZones(), out.world->options().vehicle_radius_m);
  if (!ordering.ok()) {
    PlanError e = toPlanError(ordering.error());
    e.stage = PlanStage::kOrder;
    return e;
  }
  out.ordering = std::move(*ordering);
  out.order = out.ordering.order;
  for (int index : out.order) out.ordered_m.push_back(out.points_m[index]);
  return out;
}

Result<MissionPlan, PlanError> MissionPipeline::plan(const PipelineRequest& request, double start_world_s,
                                                     const TerminationCondition& stop,
                                                     const PipelineProgress& progress) const {
  const auto started = std::chrono::steady_clock::now();
  auto report = [&](PlanStage stage, const std::string& what) {
    if (progress) progress(stage, what);
  };
  const MissionRequestData& r = request.mission;
  report(PlanStage::kOrder, "ordering " + std::to_string(r.points.size() + 2) + " points" +
                                (r.fixed_order ? " (fixed order)" : " with MMD*L"));
  auto ordered = order(r, start_world_s, stop);
  if (!ordered.ok()) return ordered.error();

  MissionPlan plan;
  plan.mission = std::move(*ordered);
  plan.seed = request.seed.value_or(options_.seed);
  const PlanBudget budget = request.budget.value_or(options_.budget);
  ReplanOptions replan = pipelineReplanOptions(options_, budget, plan.seed);
  replan.cancel = stop.sharedCancelFlag();  // the replanner keeps it for its later cycles too
  // Building and repairing a trajectory checks it segment by segment: a cancel ends it there,
  // first plan and every later replan of the mission alike.
  replan.route.trajectory.feasibility.stop_requested = stopWhen(replan.cancel);
  // Every trajectory the flight puts in force, this first one included, passes the audit first.
  plan.audit_label = std::make_shared<FlightAuditLabel>();
  plan.audit_label->vehicle_id = r.vehicle_id;
  replan.audit = flightAudit(plan.mission.world, plan.mission.limits, options_.audit, replan.horizon_s,
                             options_.audit_counters, plan.audit_label);
  const std::size_t legs = plan.mission.ordered_m.size() - 1;
  report(PlanStage::kLegs, "planning " + std::to_string(legs) + " leg" + (legs == 1 ? "" : "s") + " with " +
                               std::string(plan.mission.planner->name) + " and the trajectory through them");
  auto flight = FlightReplanner::start(plan.mission.world, plan.mission.ordered_m, plan.mission.limits, replan,
                                       start_world_s, legPathPlanner(plan.mission.planner->kind, options_.grid_legs));
  if (!flight.ok()) return requestPlanError(flight.error(), plan.mission.order, routeStage(flight.error()));
  // The trajectory is built; before anything is sampled, its real size against the caps.
  const double duration_s = (*flight)->route().built.trajectory.duration_s();
  if (auto too_large = checkTrajectorySize(duration_s, options_.sample_dt_s, options_.bounds.trajectory)) {
    too_large->stage = PlanStage::kSampling;
    return *too_large;
  }
  plan.flight = std::move(*flight);
  // Live re-ordering keeps the order's searches; without it they go now (a map per point).
  if (!r.fixed_order) {
    plan.reorder = MissionReorder::create(plan.mission.ordering.search, options_.reorder,
                                          plan.mission.world->options().vehicle_radius_m);
  }
  plan.mission.ordering.search.reset();
  // Where the vehicle comes to rest instead of passing, and why (the status and the log say so).
  for (const RoutePointStop& stop : plan.flight->route().point_stops) {
    if (stop.point >= plan.mission.order.size()) continue;
    plan.notes.push_back(requestPointName(plan.mission.order[stop.point], static_cast<int>(plan.mission.order.size())) +
                         ": stops there (zero speed): " + stop.reason);
  }
  const std::vector<std::size_t>& corner_stops = plan.flight->route().leg_corner_stops;
  for (std::size_t leg = 0; leg < corner_stops.size(); ++leg) {
    if (corner_stops[leg] == 0 || leg + 1 >= plan.mission.order.size()) continue;
    const int count = static_cast<int>(plan.mission.order.size());
    plan.notes.push_back("legs[" + std::to_string(leg) + "] (from " + requestPointName(plan.mission.order[leg], count) +
                         " to " + requestPointName(plan.mission.order[leg + 1], count) + "): stops at " +
                         std::to_string(corner_stops[leg]) + " of its corners: " + plan.flight->route().corner_stop_reason);
  }
  for (std::size_t i = 0; i < plan.flight->route().legs.size(); ++i) {
    const RouteLeg& leg = plan.flight->route().legs[i];
    if (!leg.time_capped) continue;
    std::ostringstream note;
    note << "legs[" << i << "]: the wall-clock cap of " << budget.leg_time_cap_s
         << " s stopped the search before its iteration budget; the plan is not reproducible from the seed";
    plan.notes.push_back(note.str());
  }
  plan.planning_time_s = secondsSince(started);
  return plan;
}

TrajectoryData MissionPipeline::sample(const MissionPlan& plan, const TrajectoryIdentity& identity) const {
  const FlightReplanner& flight = *plan.flight;
  const OrderedMission& mission = plan.mission;
  const double start_s = flight.trajectoryStartWorldS();
  const Trajectory& trajectory = flight.route().built.trajectory;
  // A replanned revision may have grown (a stretch flown slower): its samples stay within the cap.
  double dt_s = options_.sample_dt_s;
  const std::size_t max_samples = options_.bounds.trajectory.max_samples;
  if (max_samples > 2 && sampleCount(trajectory.duration_s(), dt_s) > max_samples) {
    dt_s = trajectory.duration_s() / static_cast<double>(max_samples - 2);
  }
  TrajectoryData data = toTrajectoryData(trajectory, world_->frame(), dt_s,
                                         static_cast<std::int64_t>(std::llround(start_s * 1e9)), identity);
  for (int index : mission.order) data.visiting_order.push_back(static_cast<std::uint32_t>(index));
  // The route's points: the first is where this revision starts (the begin point, or where the
  // vehicle takes the new trajectory over); the others are the points still to reach, copied
  // from the ordered points. A revision's first leg continues the leg it interrupted.
  const std::vector<Eigen::Vector3d> remaining = flight.remainingPoints(start_s);
  std::vector<int> route_ids;
  for (const Eigen::Vector3d& p : remaining) {
    int id = mission.order.back();
    for (std::size_t k = 0; k < mission.ordered_m.size(); ++k) {
      if (mission.ordered_m[k] == p) id = mission.order[k];
    }
    route_ids.push_back(id);
  }
  int previous = mission.order.front();
  if (!route_ids.empty()) {
    const auto at = std::find(mission.order.begin(), mission.order.end(), route_ids.front());
    if (at != mission.order.begin() && at != mission.order.end()) previous = *(at - 1);
  }
  route_ids.insert(route_ids.begin(), previous);
  for (const RouteLeg& leg : flight.route().legs) {
    if (leg.to_point >= route_ids.size()) break;
    data.legs.push_back(LegBoundaryData{static_cast<std::uint32_t>(route_ids[leg.from_point]),
                                        static_cast<std::uint32_t>(route_ids[leg.to_point]), leg.start_s, leg.end_s});
  }
  return data;
}

namespace {

// The request indices of route points (copies of the ordered points); -1 for one that is none.
std::vector<int> requestIndicesOf(const OrderedMission& mission, const std::vector<Eigen::Vector3d>& points_m) {
  std::vector<int> out;
  for (const Eigen::Vector3d& p : points_m) {
    int id = -1;
    for (std::size_t k = 0; k < mission.ordered_m.size(); ++k) {
      if (mission.ordered_m[k] == p) id = mission.order[k];
    }
    out.push_back(id);
  }
  return out;
}

}  // namespace

ReorderOutcome MissionPipeline::reorder(MissionPlan& plan, double now_s, const TerminationCondition& stop) const {
  ReorderOutcome out;
  if (!plan.reorder || !plan.flight || plan.flight->finished(now_s)) return out;
  FlightReplanner& flight = *plan.flight;
  OrderedMission& mission = plan.mission;
  // Where a new route would take over: the points passed by then are reached, and the vehicle's
  // start is there.
  const double takeover_s = flight.takeoverS(now_s);
  const std::vector<int> remaining = requestIndicesOf(mission, flight.remainingPoints(takeover_s));
  if (remaining.empty() || std::find(remaining.begin(), remaining.end(), -1) != remaining.end()) return out;
  const auto first_left = std::find(mission.order.begin(), mission.order.end(), remaining.front());
  if (first_left == mission.order.begin() || first_left == mission.order.end()) return out;
  const std::vector<int> reached(mission.order.begin() + 1, first_left);
  out.check = plan.reorder->check(mission.world->obstacles(), mission.world->noFlyZones(), now_s, reached,
                                  flight.stateAt(takeover_s).position_m, remaining, stop);
  if (!out.check.reordered()) return out;
  std::vector<Eigen::Vector3d> points;
  for (std::size_t k = 1; k < out.check.new_order.size(); ++k) points.push_back(mission.points_m[out.check.new_order[k]]);
  out.step = flight.reroute(now_s, points);
  if (!out.step.replanned) return out;
  // The order as flown: the points passed (begin first), then the new order of those left.
  std::vector<int> order(mission.order.begin(), first_left);
  order.insert(order.end(), out.check.new_order.begin() + 1, out.check.new_order.end());
  mission.order = std::move(order);
  mission.ordered_m.clear();
  for (int index : mission.order) mission.ordered_m.push_back(mission.points_m[static_cast<std::size_t>(index)]);
  return out;
}

FleetPlanOutput MissionPipeline::planFleet(const FleetRequestData& request, std::int64_t start_utc_ns,
                                           const TerminationCondition& stop) const {
  FleetMissionOptions fleet = fleetMissionOptions(options_);
  fleet.route.trajectory.feasibility.stop_requested = stopWhen(stop.sharedCancelFlag());
  FleetPlanOutput out = planFleetMission(request, *world_, fleet, start_utc_ns, stop);
  if (!out.ok()) return out;
  // Every vehicle's first trajectory passes the audit, as a single flight's does.
  const FleetAuditHook audit = fleetAudit(request);
  const double start_world_s = static_cast<double>(start_utc_ns) * 1e-9;
  for (std::size_t i = 0; i < out.flown.size() && audit; ++i) {
    const std::optional<Error> refused = audit(i, out.flown[i], start_world_s + out.delays_s[i], start_world_s, 0);
    if (!refused) continue;
    PlanError error = toPlanError(*refused);
    error.stage = PlanStage::kTrajectory;
    error.field = "vehicle_ids[" + std::to_string(i) + "]";
    out.status.state = PlanState::kFailed;
    out.status.error_code = error.code;
    out.status.field = error.field;
    out.status.message = error.describe();
    out.trajectories.clear();
    break;
  }
  return out;
}

FleetAuditHook MissionPipeline::fleetAudit(const FleetRequestData& request) const {
  auto world = world_->worldFor(request.limits.min_clearance_agl_m, request.limits.ceiling_amsl_m);
  if (!world.ok()) return {};
  return skyroute::fleetAudit(*world, toVehicleLimits(request.limits), options_.audit, options_.replan.horizon_s,
                              options_.audit_counters, request.vehicle_ids);
}

}  // namespace skyroute
