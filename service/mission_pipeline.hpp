// The one mission pipeline, DDS-free: a request in, a checked trajectory (ready to be replanned)
// and a status out. Every entry point plans through it: the daemon's engine, `skyroute plan`,
// `skyroute mission --dem`, `skyroute fleet --dem` and the benchmarks that time the product, so a
// mission tried on the command line gets the trajectory the daemon would publish.
//
// Stages (PlanStage names them in a failure):
//   validate   -- structure, numbers, limits and the planner's name (planner_registry.hpp);
//                 every point inside the DEM, above the ground plus clearance, under the ceiling
//   order      -- MMD*L cost matrix and an open TSP from begin to end (mission_order.hpp), or the
//                 given order
//   legs       -- the request's planner finds each leg's 3D path
//   trajectory -- one 7th-order minimum-snap trajectory through the legs' waypoints, checked
//                 against the vehicle's limits and the terrain and repaired (route_planner.hpp)
//   (audit)    -- the trajectory, before it is put in force, passes the audit (flight_audit.hpp),
//                 a check that is not the planner's; a refusal fails the trajectory stage
//   sampling   -- the trajectory as timed samples with ENU and WGS84 positions
// The budget is reproducible by default: an iteration count per leg, with a wall-clock cap whose
// firing the plan's notes (and so the status and the log) report.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "planning/core/termination.hpp"
#include "service/fleet_mission.hpp"
#include "service/fleet_replanner.hpp"
#include "service/flight_audit.hpp"
#include "service/flight_replanner.hpp"
#include "service/grid_leg_planner.hpp"
#include "service/mission_order.hpp"
#include "service/mission_reorder.hpp"
#include "service/mission_types.hpp"
#include "service/planner_registry.hpp"
#include "service/request_footprint.hpp"
#include "service/trajectory_data.hpp"
#include "service/world_model.hpp"

namespace skyroute {

// How much search a leg may spend: reproducible iterations, capped in wall-clock time.
struct PlanBudget {
  std::uint64_t leg_max_iterations = 3000;  // RRT* iterations per leg (0 = none: the cap alone)
  double leg_time_cap_s = 10.0;             // wall-clock cap per leg (0 = none)
};

// The pipeline's settings: the configuration's [planning] and [replanning] sections.
struct PipelineOptions {
  std::string default_planner{kDefaultRoutePlanner};  // for requests that name none
  std::uint64_t seed = 1;                 // of every plan unless a request gives its own
  PlanBudget budget;
  double sample_dt_s = 0.2;               // spacing of the trajectory samples
  MissionRequestBounds bounds;            // what a request may ask for
  MissionOrderOptions order;              // the MMD*L order grid
  GridLegOptions grid_legs;               // the grid planners' flight-band grid
  ReplanOptions replan = defaultReplanOptions();  // replan.route: corridor, LOSPO, trajectory stage
  FleetMissionOptions fleet;              // fleet requests (their trajectory stage is replan.route's)
  FleetReplanOptions fleet_replan;        // flying fleets kept clear of obstacles (fleet_replanner.hpp)
  MissionReorderOptions reorder;          // live re-ordering of flying missions (mission_reorder.hpp)
  VehicleModelDefaults vehicle;           // the model of requests that leave it to the service
  AuditOptions audit;                     // the audit every trajectory passes before it is in force
  // Where the audits are counted (the daemon's heartbeat); null: not counted.
  std::shared_ptr<AuditCounters> audit_counters;

  // The first plan's leg pipeline is RRT* on an iteration budget; a replan must come back within
  // a cycle, so its RRT* gets fewer iterations per leg (informed sampling around the current path
  // finds a detour in a few hundred).
  static ReplanOptions defaultReplanOptions();
};

// The flight's options for one plan: the configuration's replanning settings with the plan's seed
// and budget in its route (leg) stage. What plan() gives FlightReplanner, and what the benchmarks
// that time the product's legs and replans use.
ReplanOptions pipelineReplanOptions(const PipelineOptions& options, const PlanBudget& budget, std::uint64_t seed);

// Checks options that a configuration file or a command line may set. Errors name the key.
std::optional<PlanError> validatePipelineOptions(const PipelineOptions& options);

// One plan's request: the mission (points, order mode, planner, vehicle limits with clearance and
// ceiling) and, when the caller overrides the configuration, the seed and the budget.
struct PipelineRequest {
  MissionRequestData mission;
  std::optional<std::uint64_t> seed;
  std::optional<PlanBudget> budget;
};

// What the order stage found, in request numbering (0 = begin, 1..N = points, N+1 = end).
struct OrderedMission {
  const RoutePlannerInfo* planner = nullptr;
  std::vector<int> order;                  // request point indices in visiting order
  std::vector<Eigen::Vector3d> points_m;   // the request's points, ENU, request numbering
  std::vector<Eigen::Vector3d> ordered_m;  // the same in visiting order
  MissionOrder ordering;                   // method, cost, expansions, fallback reason
  std::shared_ptr<const CollisionWorld> world;  // the world of the request's clearance and ceiling
  VehicleLimits limits;
};

struct MissionPlan {
  OrderedMission mission;
  std::unique_ptr<FlightReplanner> flight;  // the trajectory (flight->route()), ready to be replanned
  // The order's MMD*L searches, kept to re-order the points left when obstacles change; null for
  // a fixed order, one point, or a Euclidean fallback (nothing to repair), or with re-ordering off.
  std::unique_ptr<MissionReorder> reorder;
  std::uint64_t seed = 0;
  std::vector<std::string> notes;            // e.g. a leg whose wall-clock cap fired
  double planning_time_s = 0.0;
  // Whom the flight's audit log lines name (its revision base follows the engine's numbering).
  std::shared_ptr<FlightAuditLabel> audit_label;
};

// What a look at changed obstacles did to a flying mission (MissionPipeline::reorder).
struct ReorderOutcome {
  ReorderCheck check;  // point indices in request numbering
  ReplanStep step;     // the flight planned through the new order (step.replanned: a new revision)
};

// Progress of a long plan: the stage that starts and a line saying what it does.
using PipelineProgress = std::function<void(PlanStage stage, const std::string& what)>;

class MissionPipeline {
 public:
  MissionPipeline(std::shared_ptr<WorldModel> world, PipelineOptions options);

  const PipelineOptions& options() const { return options_; }
  WorldModel& world() const { return *world_; }

  // The validate and order stages only. start_world_s: when the vehicle starts (world clock, UTC
  // seconds), for the obstacles in force then.
  Result<OrderedMission, PlanError> order(const MissionRequestData& request, double start_world_s,
                                          const TerminationCondition& stop = {}) const;
  // Every stage up to the checked trajectory.
  Result<MissionPlan, PlanError> plan(const PipelineRequest& request, double start_world_s,
                                      const TerminationCondition& stop = {},
                                      const PipelineProgress& progress = {}) const;
  // The sampling stage: the flight's current trajectory as the service publishes it (legs and
  // visiting order in request numbering, absolute times from the flight's start), at the
  // configured spacing, or, for a replanned revision longer than the sample cap allows (plan()
  // checked the first), at the spacing that keeps it within the cap.
  TrajectoryData sample(const MissionPlan& plan, const TrajectoryIdentity& identity) const;
  // The order stage again, live, after the obstacles changed (mission_reorder.hpp): the points the
  // flight has passed by its takeover after now_s are visited, the searches repaired, the points
  // left ordered again from where the vehicle will be; when the order changes, the flight is
  // planned through the new one and, when that gives a new revision, plan.mission's order and
  // ordered points follow (the points passed first, as flown). Nothing for a plan without
  // plan.reorder.
  ReorderOutcome reorder(MissionPlan& plan, double now_s, const TerminationCondition& stop = {}) const;
  // A fleet request (fleet_mission.hpp) with this pipeline's trajectory stage and sample spacing;
  // each vehicle's trajectory passes the audit (fleetAudit) before the plan succeeds, and a
  // refusal fails the fleet naming the vehicle (field vehicle_ids[i]; nothing is published).
  FleetPlanOutput planFleet(const FleetRequestData& request, std::int64_t start_utc_ns,
                            const TerminationCondition& stop = {}) const;
  // The audit of the request's vehicles against this pipeline's world (counted in
  // options.audit_counters), for the fleet's replanner to use on every revision; empty when the
  // world has no layer for the request's clearance and ceiling.
  FleetAuditHook fleetAudit(const FleetRequestData& request) const;

 private:
  std::shared_ptr<WorldModel> world_;
  PipelineOptions options_;
};

// The fleet stage's options: the pipeline's fleet settings with its sample spacing, trajectory
// stage and request bounds.
FleetMissionOptions fleetMissionOptions(const PipelineOptions& options);

// A request point's field name: 0 = "begin", count - 1 = "end", else "points[index - 1]".
std::string requestPointName(int index, int count);

// A route error (naming ordered points "points[k]" and legs "legs[k]") as the request's
// (begin, points[i], end), with the stage and the leg and point indices filled in.
PlanError requestPlanError(const Error& error, const std::vector<int>& order, PlanStage stage);

}  // namespace skyroute
