// The engine's private state, shared by its source files: engine.cpp (requests, cancels, obstacle
// updates and planning one request), engine_fleet.cpp (fleet requests) and engine_cycles.cpp (the
// planning workers, the replanning loop and stopping). Nothing outside the engine includes it.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "service/engine.hpp"

namespace skyroute {

struct Engine::Job {
  MissionRequestData request;                // a mission (request.vehicle_id set), or
  std::optional<FleetRequestData> fleet;     // a fleet (request left empty)
  // A flying mission recovered from the state journal: its flight is rebuilt, the trajectory
  // published before the restart kept (never answered with a status: the request was answered).
  std::optional<TrajectoryData> resume;
  std::int64_t resume_start_utc_ns = 0;      // when the recovered flight started (its first plan)
  std::shared_ptr<std::atomic<bool>> cancel = std::make_shared<std::atomic<bool>>(false);
  // A flying fleet's replan (engine_fleet.cpp), queued by the replanning loop.
  std::shared_ptr<Fleet> fleet_replan;
};

// A flying fleet: its replanner (fleet_replanner.hpp) and what the replanning loop knows of it.
struct Engine::Fleet {
  std::string request_id;
  std::unique_ptr<FleetReplanner> replanner;
  std::mutex mutex;                          // the replanner
  std::atomic<bool> ended{false};            // landed, replaced by a newer fleet or stopped
  // Under the engine's mutex: a replan job is queued or running; the world changes it checked;
  // the last step ran out of budget (the next cycle queues another).
  bool queued = false;
  std::uint64_t changes_checked = 0;
  bool retry = false;
  double lands_world_s = 0.0;                // after this the fleet is landed: a job drops it
  std::size_t pending_answered = 0;          // pending tasks in the last fleet status published
};

struct Engine::Mission {
  MissionRequestData request;
  std::shared_ptr<WorldModel> world_model;   // planned on (its frame turns ENU into WGS84)
  std::string plan_id;
  MissionPlan plan;                          // order, points and the flight being replanned
  std::shared_ptr<std::atomic<bool>> cancel;
  std::mutex mutex;                          // the flight and `ended`
  bool ended = false;                        // cancelled or replaced: no more revisions
  // A flight rebuilt after a restart: revisions count on from the journal's, and until its first
  // replan the trajectory published before the restart stays its current one.
  std::uint32_t revision_base = 0;
  std::optional<TrajectoryData> recovered;
  // The engine's count of world changes when this flight was last checked: the changes since
  // are the ones a cycle's check takes together (one replan however many there were).
  std::uint64_t changes_checked = 0;
  // A failed replan has been answered with a status since the last revision or world change
  // (a blocked vehicle fails every cycle; it is told once per change).
  bool failure_answered = false;
  // The engine's count of world changes when the order was last looked at (engine_reorder.cpp):
  // a mission whose order MMD*L chose is re-ordered at most once per change of the obstacles.
  std::uint64_t order_checked = 0;
};

// What a replanning step may change in a flying mission, kept before it when the sink's records
// can fail (EngineSink::recordsTrajectories): a revision the journal does not record is undone.
struct Engine::FlightSnapshot {
  std::unique_ptr<FlightReplanner> flight;
  std::optional<OrderedMission> order;  // kept before a look at the order (engine_reorder.cpp)
};

namespace engine_detail {

// A request answered cancelled, saying why.
PlanStatusData cancelledStatus(const MissionRequestData& r, const std::string& why);
// A fleet request answered failed (or cancelled) with the error.
FleetStatusData fleetFailed(const std::string& request_id, const PlanError& error);

}  // namespace engine_detail
}  // namespace skyroute
