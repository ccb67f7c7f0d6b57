// A fleet mission (issue 7 item 6, seed 002 in 3D): a FleetRequest's begins, tasks and ends become
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
// holds at its begin point, after its end at its end point. Every pair is sampled every
// separation_dt_s over the whole mission against min_separation_m plus the most two vehicles at
// their speed limit can close within half a sample interval, so the separation holds at every
// instant, not just at samples. A pair that comes too close is repaired by delaying the start of
// the later vehicle (request order) in delay_step_s steps until it is clear of every earlier one.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "planning/termination.hpp"
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
  double delay_step_s = 0.5;        // repair granularity (rounded to whole samples)
  double max_delay_s = 3600.0;      // a vehicle is delayed at most this much, then the plan fails
  double sample_dt_s = 0.2;         // sample spacing of the published trajectories
  std::size_t max_vehicles = 32;
  std::size_t max_tasks = 256;
  RouteOptions route;               // the trajectory stage (route.trajectory)
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
  bool ok() const { return status.state == PlanState::kSucceeded; }

  // Vehicle i's position at `t_s` after the mission start (holding at begin before, end after).
  Eigen::Vector3d positionAt(std::size_t i, double t_s) const;
};

// Structural checks (ids, counts, finite numbers, latitude/longitude ranges, limits, planner).
std::optional<PlanError> validateFleetRequest(const FleetRequestData& request, const FleetMissionOptions& options = {});

// Plans the whole fleet. start_utc_ns: when delay 0 starts (the trajectories' start times).
// Never throws; a failure comes back in status (kFailed, or kCancelled when `stop` was cancelled).
FleetPlanOutput planFleetMission(const FleetRequestData& request, WorldModel& world, const FleetMissionOptions& options,
                                 std::int64_t start_utc_ns, const TerminationCondition& stop = {});

}  // namespace skyroute
