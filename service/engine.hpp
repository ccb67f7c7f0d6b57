// The planning engine: owns the world model and the active missions, DDS-free (service/dds/
// converts at the edge, tests drive it directly). A request goes through the mission pipeline
// (mission_pipeline.hpp: order -> legs -> trajectory -> checks, the same as `skyroute plan`), and
// the mission's flight is then kept and replanned.
// Every replanning cycle (t_ref = 0.1 s, and at once after an obstacle update) each active mission
// checks the obstacles ahead and, when one will meet it, publishes a new revision.
//
// Size: a request is refused (kTooLarge) when the lower bound of its trajectory's duration or
// sample count, or its memory estimate, exceeds its bound (request_footprint.hpp), at submit and
// again on the planner thread; the pipeline checks the built trajectory before it is sampled.
// Request ids: (vehicle, request id) names one plan (request_registry.hpp).
// Stopping: every long stage (ordering, legs, trajectory building and repair, sampling) checks
// the job's cancel flag, which stop() sets; a plan that finishes after stop() began is answered
// cancelled, never succeeded.
//
// Threads: submit(), cancel() and updateObstacle() only queue or flag and return at once, so the
// DDS edge never plans on its own threads. start() runs planning workers and the replanning loop;
// without start(), planNext() and replanCycle() do the same work on the caller's thread (tests).
// Results leave through an EngineSink, called from the engine's threads (a vehicle's trajectory
// revisions in order).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "service/log_throttle.hpp"
#include "service/mission_pipeline.hpp"
#include "service/mission_types.hpp"
#include "service/no_fly_zone_data.hpp"
#include "service/obstacle_bounds.hpp"
#include "service/request_footprint.hpp"
#include "service/request_registry.hpp"
#include "service/world_model.hpp"

namespace skyroute {

struct EngineOptions {
  PipelineOptions pipeline;             // how each request is planned (mission_pipeline.hpp)
  int planning_threads = 1;             // requests planned at once
  std::size_t max_queue = 64;           // requests waiting beyond this are refused (kBusy)
  bool replanning = true;               // run the replanning loop on active missions
  // What the planning threads may use together; each has an equal share, and a request whose
  // estimate exceeds it is refused (kTooLarge). 0 = no memory guard.
  double memory_budget_mb = 2048.0;
  std::size_t max_stored_results = 1024;  // finished requests remembered to answer duplicates
  double log_repeat_window_s = 10.0;    // a repeated warning is logged once per window, with a count
  ObstacleBounds obstacles;             // what an obstacle update may describe
};

// The checks a new mission gets before it is accepted (besides the queue's room): its fields and
// bounds (validateMissionRequest), its planner, its points on the terrain and its footprint; and
// a new fleet's (validateFleetRequest). The journal's records are checked with the same at a
// restart (journal_screening.hpp), so a record that would be refused today is never replayed.
std::optional<PlanError> checkMissionAdmission(const MissionRequestData& request, const WorldModel& world,
                                               const EngineOptions& options);
std::optional<PlanError> checkFleetAdmission(const FleetRequestData& request, const EngineOptions& options);

// The footprint bounds and estimates of the engine's options (request_footprint.hpp).
FootprintOptions footprintOptions(const EngineOptions& options);
// kInvalidArgument naming the option (planning_threads, sample_dt_s, ...) when it is unusable.
Status validateEngineOptions(const EngineOptions& options);

// Where results go. Called from engine threads (never while an engine lock is held).
class EngineSink {
 public:
  virtual ~EngineSink() = default;
  virtual void publishStatus(const PlanStatusData& status) = 0;
  virtual void publishTrajectory(const TrajectoryData& trajectory) = 0;
  // The vehicle's trajectory no longer holds (its mission was cancelled).
  virtual void retractTrajectory(const std::string& vehicle_id) { (void)vehicle_id; }
  // The state of a fleet request (accepted, planning, then succeeded with the allocation, or failed).
  virtual void publishFleetStatus(const FleetStatusData& status) { (void)status; }

  // Write-ahead hooks (the state journal, journaling_sink.hpp): each is called before its event is
  // published or takes effect, and what a hook did not record is neither published nor acted on.
  // recordAccepted is called under the engine's lock, before the request is queued, so no worker
  // can answer a request before it is recorded; when it fails the request is refused
  // (journal_unavailable). recordTrajectory: a new plan (under the engine's lock, before it is
  // registered: when it fails the request fails journal_unavailable and the vehicle's mission in
  // force stays) or a new revision (under the mission's lock: when it fails the flight goes back to
  // the revision in force, which stays published). recordFleetPlan: a fleet's trajectories and
  // allocation together, all or none. recordCancel: under the engine's lock, before a cancel that
  // matches something takes effect (when it fails the cancel is refused journal_unavailable).
  virtual Status recordAccepted(const MissionRequestData& request) {
    (void)request;
    return Status::success();
  }
  virtual Status recordTrajectory(const TrajectoryData& trajectory) {
    (void)trajectory;
    return Status::success();
  }
  virtual Status recordFleetPlan(const std::vector<TrajectoryData>& trajectories, const FleetStatusData& status) {
    (void)trajectories;
    (void)status;
    return Status::success();
  }
  virtual Status recordCancel(const CancelRequestData& cancel) {
    (void)cancel;
    return Status::success();
  }
  // Whether recordTrajectory can fail: the engine then keeps a copy of each flight before a
  // replanning step, to go back to when the new revision is not recorded.
  virtual bool recordsTrajectories() const { return false; }
  virtual void recordObstacle(const ObstacleUpdateData& update) { (void)update; }
  virtual void recordNoFlyZone(const NoFlyZoneData& zone) { (void)zone; }
};

struct JournalState;

class Engine {
 public:
  using Clock = std::function<std::int64_t()>;  // UTC nanoseconds since the epoch

  // Errors: kInvalidArgument naming the option.
  static Result<std::unique_ptr<Engine>> create(std::shared_ptr<WorldModel> world, const EngineOptions& options,
                                                EngineSink& sink, Clock clock = utcNowNs);
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // Checks the request's structure at once (a failed status names the field) and queues it.
  // Returns the error it answered with, if any.
  std::optional<PlanError> submit(MissionRequestData request);
  // A fleet (fleet_mission.hpp): checked at once (a failed fleet status names the field), queued
  // with the missions and planned on the same workers; answered with one trajectory per vehicle and
  // a fleet status (an active mission of one of the vehicles ends, its trajectory replaced). The
  // fleet then flies (pipeline.fleet_replan.enabled): after each change of the obstacles the
  // replanning loop queues a replan of the fleet on a planning worker (fleet_replanner.hpp), which
  // replans the vehicles that would meet an obstacle, keeping the whole fleet separated, moves
  // tasks a vehicle can no longer reach to others, and publishes new revisions only for the
  // vehicles that changed, with a replanned fleet status. A newer fleet with one of its vehicles
  // ends it.
  std::optional<PlanError> submitFleet(FleetRequestData request);
  // Stops a queued or in-flight plan, or ends an active mission; answers with a cancelled status.
  // When nothing matches, answers with a failed status naming what was not found (addressed to
  // the canceller) and returns false.
  bool cancel(const CancelRequestData& request);
  // Applies an obstacle update to the world and wakes the replanning loop. Bad updates are refused.
  std::optional<PlanError> updateObstacle(const ObstacleUpdateData& update);
  // Sets or lifts a published no-fly zone and wakes the replanning loop: a flight whose trajectory
  // now crosses it replans like one an obstacle blocks. Bad geometry is refused naming the zone.
  std::optional<PlanError> updateNoFlyZone(const NoFlyZoneData& zone);

  // The same work as the threads, on the caller's thread.
  bool planNext();              // plans the oldest queued request; false when none was queued
  std::size_t replanCycle();    // one cycle at clock(); returns the revisions published

  void start();  // planning workers and the replanning loop
  void stop();   // cancels in-flight plans, ends the threads (idempotent)
  bool running() const { return running_.load(); }

  // Tunables for the requests that follow (the daemon's SIGHUP reload); a new planning_threads
  // starts or retires workers (a retiring worker finishes its plan first). Errors as create().
  Status setOptions(const EngineOptions& options);
  EngineOptions options() const;
  // A new terrain (the daemon's SIGHUP reload), refused (kInvalidArgument naming "terrain.dem")
  // while a mission is active or a request is queued or being planned: their trajectories were
  // planned and checked on the old terrain. The obstacles in force move over to it.
  Status replaceWorld(std::shared_ptr<WorldModel> world);
  Status canReplaceWorld() const;  // the refusal replaceWorld would give now, if any
  // Every active mission's current trajectory, sampled again (to publish on a new DDS domain).
  std::vector<TrajectoryData> currentTrajectories() const;
  // After a restart, before start() (engine_recovery.cpp): the journal's obstacles and no-fly
  // zones go into the world, every vehicle's trajectory is published again as it was (same plan,
  // revision and samples) and the fleets' allocations with them, requests accepted but never
  // planned are queued again, and each flying mission's flight is rebuilt from its request on a
  // worker so the replanning loop goes on with it (its next revision follows the journal's).
  void recover(const JournalState& state);
  // Sharded daemons (engine_handover.cpp). A vehicle this daemon no longer plans: its queued
  // request is dropped, a plan in progress cancelled, its mission ended, all without a status or a
  // retraction (the daemon that takes the vehicle answers from now on; its caller stops publishing
  // for the vehicle before calling this).
  void release(const std::string& vehicle_id);
  // The same for a fleet request not yet planned (queued or in progress).
  void releaseFleet(const std::string& request_id);
  // A vehicle taken over from another daemon in flight: the flight is rebuilt from its request as
  // a restart does (recover()), started when `last` started, and goes out at once as revision
  // last.revision + 1 of last.plan_id, then is replanned as usual. `last` names the trajectory in
  // force (its samples are not needed). Answers no status: the request was answered.
  void resumeFlight(const MissionRequestData& request, const TrajectoryData& last, std::int64_t flight_start_utc_ns);
  // A hot standby taking over: the readers' last revision of the vehicle's plan came from the
  // primary (wire_revision). When this engine's current revision of that plan is neither it nor
  // the one after (the two daemons' replans drifted apart), the current trajectory is numbered
  // wire_revision + 1 and later revisions count on from there. Returns the new number, or nothing
  // when the numbering already follows (or the vehicle flies another plan here).
  std::optional<std::uint32_t> followRevision(const std::string& vehicle_id, const std::string& plan_id,
                                              std::uint32_t wire_revision);
  // Plan ids become "<vehicle>-<tag>-<n>" (before start()): daemons that plan the same vehicles in
  // turn (a shard group) never give two plans one id, their counters being their own.
  void setPlanIdTag(const std::string& tag);

  ServiceStatusData status(const std::string& service_id) const;
  std::size_t activeMissions() const;
  std::size_t queueLength() const;
  std::uint64_t replans() const { return replans_.load(); }
  std::shared_ptr<WorldModel> world() const;

 private:
  struct Job;
  struct Mission;
  struct Fleet;
  Engine(std::shared_ptr<WorldModel> world, const EngineOptions& options, EngineSink& sink, Clock clock);
  // Checks a request with `validate` (under the lock: it reads the options), refuses it when the
  // engine stops or the queue is full (kBusy), else queues the job. Returns the refusal.
  using Validator = std::function<std::optional<PlanError>(const EngineOptions&)>;
  std::optional<PlanError> enqueue(std::unique_ptr<Job> job, const Validator& validate);
  std::optional<PlanError> queueRefusal() const;  // shutting down or queue full (under mutex_)
  void plan(Job& job);
  // Takes the oldest queued job into in_flight_ (the caller holds mutex_); null when none.
  std::unique_ptr<Job> takeJobLocked();
  // Plans a taken job and drops it from in_flight_.
  void planTaken(std::unique_ptr<Job> job);
  void planFleetJob(Job& job);
  void replanFleetJob(Job& job);  // one step of a flying fleet's replanner (engine_fleet.cpp)
  // The cycle's look at the flying fleets: a fleet whose world changed gets a replan job.
  void queueFleetReplans(std::uint64_t changes, double now_s);
  void planResumed(Job& job);  // a recovered flying mission's flight (engine_recovery.cpp)
  // Write-ahead of a flying mission's new revision `data` (under the mission's lock): true when
  // recorded; otherwise the flight (and the order) go back to `before`, the revision in force
  // stays, the requester is told once per change of the world (a non-terminal status with
  // journal_unavailable), and false.
  struct FlightSnapshot;
  bool recordRevision(Mission& mission, const TrajectoryData& data, FlightSnapshot& before, double latency_ms);
  void status(const MissionRequestData& request, PlanState state, double planning_time_s = 0.0);
  // Publishes a request's final status and records it for duplicates of the request.
  void finish(const PlanStatusData& status);
  // The published form of a mission's current trajectory (the pipeline's sampling stage).
  TrajectoryData trajectoryOf(const Mission& mission) const;
  // A replan that found nothing better and no hold either, answered (once per change of the
  // world) with a status that is not terminal: state replanned (holding when a hold is in force),
  // the error, and the revision that stays in force.
  void publishReplanFailure(const MissionRequestData& request, const Error& failure, std::uint32_t revision,
                            double latency_ms, std::uint64_t coalesced, bool holding);
  // The hold just published as `revision` (ReplanStep::holding): a non-terminal holding status
  // naming why no plan was found.
  void publishHold(const MissionRequestData& request, const ReplanStep& step, std::uint32_t revision);
  // The cycle's look at a flying mission's order after the world changed (engine_reorder.cpp),
  // under the mission's lock (`lock`, released when it publishes): when the points left are
  // better flown in a new order, publishes that revision with a reordered status and returns true.
  bool reorderMission(Mission& mission, std::unique_lock<std::mutex>& lock, double now_s, std::uint64_t changes,
                      std::uint64_t coalesced);
  void startWorkers(int count);  // under mutex_
  void workerLoop();
  void replanLoop();

  EngineSink& sink_;
  Clock clock_;

  mutable std::mutex mutex_;  // world_, options_, queue_, in_flight_, missions_, registry_, workers
  std::shared_ptr<WorldModel> world_;
  EngineOptions options_;
  std::deque<std::unique_ptr<Job>> queue_;
  std::vector<Job*> in_flight_;                                // jobs being planned
  std::map<std::string, std::shared_ptr<Mission>> missions_;   // vehicle id -> active mission
  std::map<std::string, std::shared_ptr<Fleet>> fleets_;       // request id -> flying fleet
  RequestRegistry registry_;
  LogThrottle throttle_;                                       // repeated warnings
  int running_workers_ = 0;                                    // workers not retired
  std::vector<std::thread::id> retired_;                       // exited workers, to join
  std::condition_variable work_cv_;
  std::condition_variable replan_cv_;
  bool replan_wake_ = false;
  std::atomic<bool> running_{false};
  std::atomic<bool> stopping_{false};
  std::atomic<std::uint64_t> replans_{0};
  // Every flight's audits (the heartbeat's counts); options_.pipeline.audit_counters points here.
  std::shared_ptr<AuditCounters> audit_counters_ = std::make_shared<AuditCounters>();
  std::uint64_t plan_counter_ = 0;
  std::string plan_id_tag_;                                    // "" = "<vehicle>-<n>"
  std::vector<std::thread> workers_;
  std::thread replanner_;
};

}  // namespace skyroute
