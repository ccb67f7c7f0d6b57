// A fleet mission (the GMTPA paper, seed 002, in 3D): a FleetRequest's begins, tasks and ends become
// cells of a flight-band grid, GMTPA (greedy Algorithm 1 + conflict-free space-time paths) plans
// them, each vehicle's grid path is lifted to 3D and flown through the trajectory stage, and the
// continuous trajectories are checked for a minimum separation at every instant and repaired by
// delaying starts. DDS-free: the engine and the tests call it directly.
//
// Geometry:
// - The band: from the ground clearance (plus the vehicle radius) up to the highest request point
//   plus band_margin_m (under the ceiling). The grid's cell edge makes it at most
//   max_cells_per_axis cells along the terrain's longer side (never below the DEM's cell).
// - Every vehicle cruises at the band's top, the altitude the grid is free at: it climbs
//   vertically over its begin point, follows its grid path's cell centres (waits and straight
//   runs collapsed), passes over each task's east/north position at the cruise altitude (a task is
//   an overflight; its altitude only raises the band), returns over its depot and descends.
// - Depot = the begin point's cell (GMTPA returns every vehicle to its depot, eq. 7). When a
//   vehicle's end differs from its begin, the vehicle flies on from over its depot straight to
//   over its end at the cruise altitude and descends there; that segment must be clear (else the
//   error names "ends[i]"). A vehicle left without tasks whose end is its begin stays there (its
//   trajectory holds the begin point for one sample interval).
//
// Separation: the trajectory stage re-times the path by the cruise speed, so the grid plan's
// one-cell-per-step guarantee does not carry over to the flown curves. Before its start a vehicle
// holds at its begin point, after its end at its end point. The check certifies the minimum
// separation over continuous time, not only at samples: every pair is evaluated every
// separation_dt_s; between two samples t0 < t1 the distance can fall at most at the pair's
// relative speed, bounded by the sum of both vehicles' speed bounds there (each segment's
// velocity polynomials in Bernstein form), so it stays at least (d(t0) + d(t1) - v_rel h) / 2 over
// the interval. Where that bound does not clear the separation, the interval is halved (the
// distance evaluated at its middle) until it does, a sample falls short (a loss of separation), or
// the interval is shorter than separation_min_interval_s (counted as a loss: a pass is a proof).
// A pair that comes too close is repaired by delaying the start of the later vehicle (request
// order) in delay_step_s steps until it is clear of every earlier one.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "planning/core/termination.hpp"
#include "planning/fleet/fleet_paths.hpp"
#include "service/mission_types.hpp"
#include "service/route_planner.hpp"
#include "service/world_model.hpp"
#include "trajectory/trajectory.hpp"

namespace skyroute {

inline constexpr const char* kFleetPlannerGreedy = "gmtpa";

struct FleetMissionOptions {
  int max_cells_per_axis = 128;     // grid size along the terrain's longer side
  double band_margin_m = 200.0;     // band top above the highest request point
  double min_separation_m = 0.0;    // 3D distance kept between any two vehicles; 0 = the grid's cell edge
  double separation_dt_s = 0.05;    // sampling of the separation check
  double separation_min_interval_s = 1e-4;  // bisection stops here; still unproven counts as too close
  double delay_step_s = 0.5;        // repair granularity (rounded to whole samples)
  double max_delay_s = 3600.0;      // a vehicle is delayed at most this much, then the plan fails
  double sample_dt_s = 0.2;         // sample spacing of the published trajectories
  std::size_t max_vehicles = 32;
  std::size_t max_tasks = 256;
  RouteOptions route;               // the trajectory stage (route.trajectory)
  VehicleLimitBounds limit_bounds;  // what the shared limits may ask for
  TrajectorySizeBounds trajectory_bounds;  // each vehicle's trajectory, checked before sampling
  // The model of requests that leave it to the service. Fleets fly multirotors only: their
  // space-time plans wait in place and stop at depots, which a fixed wing cannot.
  VehicleModel default_model = VehicleModel::kMultirotor;
};

struct FleetPlanOutput {
  FleetStatusData status;                      // kSucceeded, or kFailed with code, field, message
  std::vector<TrajectoryData> trajectories;    // one per vehicle, request order (on success)
  std::vector<Trajectory> flown;               // the continuous trajectories, each from its own t = 0
  std::vector<double> delays_s;                // start of flown[i] after the mission start
  std::vector<Eigen::Vector3d> begins_m;       // ENU, request order
  std::vector<Eigen::Vector3d> tasks_m;
  std::vector<Eigen::Vector3d> ends_m;
  double cell_size_m = 0.0;
  double cruise_altitude_m = 0.0;
  // What a replanner of the flying fleet needs (fleet_replanner.hpp): the flight band's grid, each
  // vehicle's space-time grid path (request order) and the separation certified.
  std::shared_ptr<const GridLayer> grid;
  std::vector<VehiclePlan> grid_paths;
  bool ok() const { return status.state == PlanState::kSucceeded; }

  // Vehicle i's position at `t_s` after the mission start (holding at begin before, end after).
  Eigen::Vector3d positionAt(std::size_t i, double t_s) const;
};

// An upper bound on the speed of `trajectory` over [from_s, to_s] (its own clock; 0 outside its
// duration, where it holds still): the largest, over the segments overlapping the interval, of
// the norm of the per-axis bounds of |velocity| from the Bernstein coefficients.
double speedBoundMps(const Trajectory& trajectory, double from_s, double to_s);

struct SeparationCheckOptions {
  double separation_m = 0.0;
  double sample_dt_s = 0.05;       // delays in whole samples reuse the cached positions
  double min_interval_s = 1e-4;    // bisection floor; an interval still unproven there fails
};

struct SeparationVerdict {
  bool clear = true;                        // proven: every pair >= separation at every instant
  std::size_t vehicle_a = 0;                // when not clear: the first pair found too close
  std::size_t vehicle_b = 0;
  double time_s = 0.0;                      // and when (mission time)
  double closest_m = std::numeric_limits<double>::infinity();  // least distance evaluated
  std::size_t refinements = 0;              // distances evaluated between samples
};

// Certifies the separation of the trajectories flown[i] started delays_s[i] after the mission
// start (holding at their first point before and their last point after), over all pairs.
SeparationVerdict checkFleetSeparation(const std::vector<Trajectory>& flown, const std::vector<double>& delays_s,
                                       const SeparationCheckOptions& options);

// Start delays that make checkFleetSeparation pass: in request order, each vehicle is held back
// delay_step_s (rounded to whole samples) at a time until it is proven clear of every earlier
// one. failed_vehicle names the first that would need more than max_delay_s; stopped is set when
// `stop` fired. On success delays_s holds one delay per vehicle (the first is always 0).
struct SeparationRepair {
  std::vector<double> delays_s;
  std::optional<std::size_t> failed_vehicle;
  bool stopped = false;
  double closest_m = std::numeric_limits<double>::infinity();  // least distance evaluated, final schedule
  std::size_t repaired = 0;                 // vehicles delayed
};
SeparationRepair repairFleetSeparation(const std::vector<Trajectory>& flown, const SeparationCheckOptions& options,
                                       double delay_step_s, double max_delay_s, const TerminationCondition& stop = {});

// Structural checks (ids, counts, finite numbers, latitude/longitude ranges, limits, planner).
std::optional<PlanError> validateFleetRequest(const FleetRequestData& request, const FleetMissionOptions& options = {});

// Plans the whole fleet. start_utc_ns: when delay 0 starts (the trajectories' start times).
// Never throws; a failure comes back in status (kFailed, or kCancelled when `stop` was cancelled).
FleetPlanOutput planFleetMission(const FleetRequestData& request, WorldModel& world, const FleetMissionOptions& options,
                                 std::int64_t start_utc_ns, const TerminationCondition& stop = {});

}  // namespace skyroute
