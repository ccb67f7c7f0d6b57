// A flying fleet (fleet_mission.hpp) kept conflict-free while obstacles change (seed 002's
// moving obstacles, eq. 2-7, in the daemon): the fleet's request, flight-band grid, each vehicle's
// trajectory in force (with the world time it started and its revision) and the tasks it serves
// when (a task is served once the trajectory in force passes over it).
//
// A step at world time now_s:
// - Affected vehicles: those whose trajectory in force, from now on, comes within margin_m (plus
//   the vehicle radius) of an obstacle where the world predicts it (each sample of the whole
//   remaining flight, every check_dt_s).
// - Each affected vehicle is replanned from its state at takeover = now + lead_s; the trajectory
//   in force is kept up to then (the same curve: continuous to the jerk). Candidates, the first
//   that passes the checks wins:
//     a detour: space-time A* on the fleet grid (steps of one cell at the cruise speed) from the
//       takeover cell through its remaining tasks to its depot, with the cells the other vehicles
//       (their trajectories in force, grown by the separation) and the obstacles (predicted,
//       grown by their size, the vehicle radius and the margin) hold at each step blocked, flown
//       from the takeover state at the cruise altitude;
//     a step aside (tried after the detour when the vehicle is below the band at the takeover:
//       climbing over its begin, not yet launched, or descending onto its end): a hover there
//       would stay on the track of an obstacle that reaches the altitudes it passes through (a
//       column reaches them all), so from a stop it moves at its altitude across that track,
//       beyond the obstacle's reach by the margin and a grid cell (its side first, then the
//       other), holds there or not until the obstacle's predicted motion has taken it past, then
//       climbs there to the band and flies the same search from there at the time it arrives; a
//       vehicle with nothing left to serve that is over its end lands from beside the track
//       instead of climbing back;
//     a wait: a stop from the takeover state, a hover of waits_s[k] (the space-time plan's wait,
//       which a flown curve cannot otherwise keep), then the same search from the hover's step.
//       A vehicle still on the band whose descent an obstacle will cross waits it out this way.
//   The checks are in continuous time against the other vehicles' trajectories in force (the
//   separation certificate of checkFleetSeparation, pair by pair) and the obstacles' predicted
//   motion (sampled every check_dt_s; the margin covers the motion between samples), so the
//   grid's timing, which a spline re-times, is a guide and never the proof.
// - When no candidate passes, the vehicle's tasks that an obstacle covers are dropped (then all
//   its remaining tasks) and it flies the rest; the dropped tasks are pending: each step offers
//   them to the vehicles still flying, cheapest insertion (straight-line length) first, each
//   insertion a candidate that must pass the same checks. A task no vehicle can take stays
//   pending; it is offered again at the next step that follows a change of the world.
// - Only the vehicles whose trajectory changed get a new revision (revision + 1, same plan id).
//   A vehicle for which no candidate passes keeps its revision and is reported (unresolved), e.g.
//   when the obstacle reaches it before it can stop and step aside, or the step aside meets
//   another vehicle, the terrain or another obstacle.
// - Work is bounded by budget_s per step: the vehicles not reached stay marked and the next step
//   goes on with them.
// DDS-free: the engine drives it on a planning worker; the tests drive it with a world clock.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "planning/core/termination.hpp"
#include "service/fleet_mission.hpp"
#include "service/mission_types.hpp"
#include "service/world_model.hpp"
#include "trajectory/trajectory.hpp"

namespace skyroute {

// The audit a fleet vehicle's revision passes before it is adopted (flight_audit.hpp, fleetAudit):
// nothing when it passes, else the refusal (field "audit"), already counted and logged.
using FleetAuditHook = std::function<std::optional<Error>(std::size_t vehicle, const Trajectory& trajectory,
                                                          double start_world_s, double now_s, std::uint32_t revision)>;

struct FleetReplanOptions {
  bool enabled = true;              // the engine keeps and replans its fleets
  double lead_s = 1.0;              // takeover this long after the step's time
  double check_dt_s = 0.25;         // obstacle samples along each trajectory
  double margin_m = 30.0;           // room kept from every obstacle beyond the vehicle radius
  double budget_s = 0.5;            // wall time of one step (candidates stop when it runs out)
  std::vector<double> waits_s = {10.0, 30.0, 60.0, 120.0};  // hovers tried after the detour
  std::uint64_t max_expansions = 200'000;                  // per space-time search
  // Every candidate revision passes it before it is adopted (the engine sets it; unset: none).
  FleetAuditHook audit;
};

// One vehicle of the flying fleet.
struct FleetVehicleFlight {
  Trajectory trajectory;            // in force
  double start_world_s = 0.0;       // its t = 0 on the world clock
  std::uint32_t revision = 0;
  std::vector<std::uint32_t> tasks;        // every task it serves, in order (served ones first)
  std::vector<double> task_times_world_s;  // when the trajectory in force (or an earlier one) is over each
  TrajectoryData data;              // the published form of the revision in force
};

struct FleetReplanStep {
  std::vector<std::size_t> changed;      // vehicles with a new revision (request order)
  std::vector<std::size_t> affected;     // vehicles found meeting an obstacle
  std::vector<std::uint32_t> reallocated;  // tasks that moved to another vehicle
  std::vector<std::uint32_t> pending;    // tasks no vehicle serves now
  std::vector<std::size_t> unresolved;   // vehicles still meeting an obstacle (no candidate passed)
  bool unfinished = false;               // the budget ran out before every affected vehicle was seen
  std::size_t candidates = 0;            // trajectories built and checked
  double latency_ms = 0.0;
};

class FleetReplanner {
 public:
  // plan: a successful planFleetMission output (grid and grid paths set) whose delay 0 is
  // start_world_s.
  static Result<std::unique_ptr<FleetReplanner>> create(const FleetRequestData& request, const FleetPlanOutput& plan,
                                                         std::shared_ptr<WorldModel> world,
                                                         const FleetMissionOptions& mission_options,
                                                         const FleetReplanOptions& options, double start_world_s);

  FleetReplanStep step(double now_s, const TerminationCondition& stop = {});

  // Whether any vehicle's trajectory in force meets an obstacle after now_s (the step's test).
  bool anyAffected(double now_s) const;
  bool finished(double now_s) const;   // every vehicle at its end and no task pending

  const FleetRequestData& request() const { return request_; }
  std::size_t vehicleCount() const { return vehicles_.size(); }
  const FleetVehicleFlight& vehicle(std::size_t i) const { return vehicles_[i]; }
  const std::set<std::uint32_t>& pendingTasks() const { return pending_; }
  Eigen::Vector3d positionAt(std::size_t i, double world_s) const;
  // The status after a step: state replanned, the allocation in force (every task a vehicle
  // serves, served or not), the delays of the first plan, makespan and separation kept; an
  // unresolved vehicle (kUnreachable, "vehicle_ids[i]") or else a pending task ("tasks[j]") is
  // named in the error fields.
  FleetStatusData status(double latency_s) const;
  double startWorldS() const { return start_world_s_; }  // the mission start (delay 0)
  double separationM() const { return separation_m_; }
  double cellSizeM() const { return plan_cell_m_; }
  double cruiseAltitudeM() const { return cruise_m_; }
  const GridLayer& grid() const { return *grid_; }

 private:
  FleetReplanner() = default;
  struct Candidate;
  // World time of the first sample of vehicle i's trajectory `t` (started at start_s), from
  // from_s on, that comes too close to an obstacle; nullopt when none.
  std::optional<double> obstacleHit(const Trajectory& t, double start_s, double from_s) const;
  bool separatedFromOthers(std::size_t i, const Trajectory& t, double start_s, double from_s) const;
  // The first candidate for vehicle i flying `tasks` from the takeover that passes the checks.
  std::optional<Candidate> replanVehicle(std::size_t i, const std::vector<std::uint32_t>& tasks, double now_s,
                                         const TerminationCondition& stop, std::size_t& built) const;
  // A place beside an obstacle's track, at the altitude the vehicle is at below the band, to step
  // to before it climbs (or, with land, descends from there onto its end); with hold_until_s
  // (world time), held there until then.
  struct Escape {
    Eigen::Vector2d xy;
    double hold_until_s = 0.0;
    bool land = false;
  };
  std::optional<Candidate> buildCandidate(std::size_t i, const std::vector<std::uint32_t>& tasks, double now_s,
                                          double takeover_s, double wait_s, const TerminationCondition& stop,
                                          const Escape* escape = nullptr) const;
  // The trajectory from rest to rest along path_m (checked against the terrain and fixed
  // obstacles), starting at world time start_world_s; nullopt when the trajectory stage fails.
  std::optional<Trajectory> restToRest(const std::vector<Eigen::Vector3d>& path_m, double start_world_s) const;
  void adopt(std::size_t i, Candidate candidate);
  std::nullopt_t rejected(std::size_t i, double wait_s, const char* why) const;  // logged (debug)
  // Vehicle i's tasks not yet served at world_s (in order).
  std::vector<std::uint32_t> remainingTasks(std::size_t i, double world_s) const;
  bool taskCovered(std::uint32_t task, double from_s, double to_s) const;  // an obstacle over it meanwhile

  FleetRequestData request_;
  std::shared_ptr<WorldModel> world_model_;
  std::shared_ptr<const CollisionWorld> world_;
  std::shared_ptr<const GridLayer> grid_;
  FleetMissionOptions mission_options_;
  FleetReplanOptions options_;
  VehicleLimits limits_;
  std::vector<FleetVehicleFlight> vehicles_;
  std::vector<Eigen::Vector3d> begins_m_, tasks_m_, ends_m_;
  std::vector<double> delays_s_;
  std::set<std::uint32_t> pending_;
  std::set<std::size_t> marked_;   // affected vehicles a step has not reached yet
  std::set<std::size_t> unresolved_;  // affected vehicles no candidate could be found for
  double start_world_s_ = 0.0;
  double separation_m_ = 0.0;
  double cruise_m_ = 0.0;
  double plan_cell_m_ = 0.0;
  double step_s_ = 1.0;            // one grid step: a cell at the cruise speed
  std::int32_t makespan_steps_ = 0;
};

}  // namespace skyroute
