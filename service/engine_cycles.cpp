// The engine's threads: the planning workers that take queued requests, the replanning loop that
// steps every active mission each cycle (t_ref, or at once after an obstacle update), and stop().
// A cycle takes every world change since the last one together: one step, so at most one replan,
// per vehicle however many updates arrived. A step that finds nothing better puts the vehicle on
// hold: a new revision that keeps the trajectory as far as it is clear, then stops (a fixed wing:
// loiters), published with a non-terminal holding status naming why. When not even a hold does better (or one is in force
// already and still clear), the step is answered with a non-terminal status (the error, the
// revision kept), once per change of the world.
#include <algorithm>
#include <chrono>
#include <thread>

#include <spdlog/spdlog.h>

#include "service/engine_state.hpp"

namespace skyroute {

using engine_detail::cancelledStatus;
using engine_detail::fleetFailed;

std::size_t Engine::replanCycle() {
  const double now_s = static_cast<double>(clock_()) * 1e-9;
  const std::shared_ptr<WorldModel> world_model = world();
  world_model->expire(now_s);
  throttle_.flush();
  // Every change of the world up to here is checked in this cycle, by one step per flight:
  // updates that arrived since the last cycle are coalesced into at most one replan per vehicle.
  const std::uint64_t changes = world_model->version();
  std::vector<std::shared_ptr<Mission>> missions;
  {
    std::lock_guard lock(mutex_);
    if (!options_.replanning) return 0;
    for (const auto& [vehicle, mission] : missions_) missions.push_back(mission);
  }
  const auto started = std::chrono::steady_clock::now();
  std::size_t published = 0;
  const bool journaled = sink_.recordsTrajectories();
  for (const std::shared_ptr<Mission>& mission : missions) {
    if (stopping_) break;
    std::unique_lock mission_lock(mission->mutex);
    if (mission->ended) continue;
    if (mission->plan.flight->finished(now_s)) {
      mission->ended = true;
      mission_lock.unlock();
      std::lock_guard lock(mutex_);
      if (auto it = missions_.find(mission->request.vehicle_id); it != missions_.end() && it->second == mission) {
        missions_.erase(it);
        spdlog::info("event=mission_completed request={} vehicle={} plan={}", mission->request.request_id,
                     mission->request.vehicle_id, mission->plan_id);
      }
      continue;
    }
    const std::uint64_t coalesced = changes - std::min(changes, mission->changes_checked);
    mission->changes_checked = changes;
    if (coalesced > 0) mission->failure_answered = false;
    if (reorderMission(*mission, mission_lock, now_s, changes, coalesced)) {
      ++published;
      continue;  // a new revision this cycle; the next cycle checks it like any other
    }
    FlightSnapshot before;
    if (journaled) before.flight = std::make_unique<FlightReplanner>(*mission->plan.flight);
    const ReplanStep step = mission->plan.flight->step(now_s);
    std::optional<TrajectoryData> made;  // a new revision, recorded before it goes out
    if (step.holding || step.replanned) {
      made = trajectoryOf(*mission);
      if (!recordRevision(*mission, *made, before, step.latency_ms)) continue;
    }
    if (step.holding) {
      mission->failure_answered = true;  // the hold is the answer to this change of the world
      const TrajectoryData& data = *made;
      sink_.publishTrajectory(data);
      mission_lock.unlock();
      ++published;
      spdlog::info("event=replan_hold request={} vehicle={} plan={} revision={} latency_ms={:.1f} updates_coalesced={} "
                   "reason=\"{}\"",
                   mission->request.request_id, mission->request.vehicle_id, mission->plan_id, data.revision,
                   step.latency_ms, coalesced, step.failure ? step.failure->describe() : std::string());
      publishHold(mission->request, step, data.revision);
    } else if (step.replanned) {
      mission->failure_answered = false;
      const TrajectoryData& data = *made;
      sink_.publishTrajectory(data);
      mission_lock.unlock();
      ++replans_;
      ++published;
      spdlog::info("event=replanned request={} vehicle={} plan={} revision={} latency_ms={:.1f} updates_coalesced={}",
                   mission->request.request_id, mission->request.vehicle_id, mission->plan_id, data.revision,
                   step.latency_ms, coalesced);
      status(mission->request, PlanState::kReplanned, step.latency_ms * 1e-3);
    } else if (step.failure) {
      const bool answer = !mission->failure_answered;
      mission->failure_answered = true;
      const std::uint32_t revision = mission->revision_base + mission->plan.flight->revision();
      const bool holding = mission->plan.flight->holding();
      mission_lock.unlock();
      if (answer && !stopping_) {
        // A fixed wing with no clear loiter circle: the answer says so too.
        Error failure = *step.failure;
        if (step.hold_failure) failure.message += "; and no hold: " + step.hold_failure->message;
        publishReplanFailure(mission->request, failure, revision, step.latency_ms, coalesced, holding);
      }
      // A blocked vehicle fails every cycle (10 Hz) until the obstacle moves: one line per window.
      throttle_.warn("replan_failed:" + mission->request.vehicle_id + ":" + step.failure->field,
                     fmt::format("event=replan_failed request={} vehicle={} field={} message=\"{}\"",
                                 mission->request.request_id, mission->request.vehicle_id, step.failure->field,
                                 step.failure->message));
    }
  }
  if (!stopping_) queueFleetReplans(changes, now_s);
  spdlog::debug("event=replan_cycle flights={} replanned={} world_version={} ms={:.1f}", missions.size(), published,
                changes, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count());
  return published;
}

bool Engine::recordRevision(Mission& mission, const TrajectoryData& data, FlightSnapshot& before, double latency_ms) {
  const Status recorded = sink_.recordTrajectory(data);
  if (recorded.ok()) return true;
  // Not published: the flight goes back to the revision in force, which the vehicle flies on,
  // and the next cycles try again.
  if (before.flight) mission.plan.flight = std::move(before.flight);
  if (before.order) mission.plan.mission = std::move(*before.order);
  const MissionRequestData& r = mission.request;
  const std::uint32_t revision = mission.revision_base + mission.plan.flight->revision();
  throttle_.warn("revision_not_journaled:" + r.vehicle_id,
                 fmt::format("event=revision_not_journaled request={} vehicle={} plan={} revision={} message=\"{}\"",
                             r.request_id, r.vehicle_id, mission.plan_id, data.revision, recorded.error().message));
  if (!mission.failure_answered && !stopping_) {
    mission.failure_answered = true;  // told once per change of the world, as a failed replan
    PlanError error{PlanErrorCode::kJournalUnavailable, "service.state_dir",
                    "no new revision: the state journal cannot record it (" + recorded.error().message + "); revision " +
                        std::to_string(revision) + " stays in force"};
    error.stage = PlanStage::kReplan;
    PlanStatusData s = PlanStatusData::failed(r, error, latency_ms * 1e-3);
    s.state = mission.plan.flight->holding() ? PlanState::kHolding : PlanState::kReplanned;
    sink_.publishStatus(s);  // under the mission's lock: a status only, nothing takes that lock
  }
  return false;
}

void Engine::publishReplanFailure(const MissionRequestData& request, const Error& failure, std::uint32_t revision,
                                  double latency_ms, std::uint64_t coalesced, bool holding) {
  // Not terminal: the mission goes on with the revision in force, and the next cycles try again.
  PlanError error = toPlanError(failure);
  error.stage = PlanStage::kReplan;
  error.message = "no new revision: " + error.message + "; revision " + std::to_string(revision) +
                  (holding ? " (a hold) stays in force" : " stays in force");
  PlanStatusData s = PlanStatusData::failed(request, error, latency_ms * 1e-3);
  s.state = holding ? PlanState::kHolding : PlanState::kReplanned;
  spdlog::info("event=replan_answered request={} vehicle={} revision={} code={} updates_coalesced={}", request.request_id,
               request.vehicle_id, revision, to_string(error.code), coalesced);
  sink_.publishStatus(s);
}

void Engine::publishHold(const MissionRequestData& request, const ReplanStep& step, std::uint32_t revision) {
  // Not terminal: the revision just published keeps the trajectory as far as it is clear, then
  // stops and waits; the next cycles plan on from it. The error says why no plan was found.
  PlanError error = step.failure ? toPlanError(*step.failure) : PlanError{PlanErrorCode::kUnreachable, "replan", ""};
  error.stage = PlanStage::kReplan;
  // A fixed wing cannot stop: its hold ends in a loiter circle it flies until a plan is found.
  error.message = "holding: revision " + std::to_string(revision) + " keeps the trajectory as far as it is clear, then " +
                  (step.loiter ? "loiters (a fixed wing: a circle at or above its minimum airspeed)" : "stops and waits") +
                  "; no new plan: " + error.message;
  PlanStatusData s = PlanStatusData::failed(request, error, step.latency_ms * 1e-3);
  s.state = PlanState::kHolding;
  sink_.publishStatus(s);
}

void Engine::startWorkers(int count) {
  while (running_workers_ < count) {
    ++running_workers_;
    workers_.emplace_back([this] { workerLoop(); });
  }
}

void Engine::workerLoop() {
  for (;;) {
    std::unique_ptr<Job> job;
    {
      std::unique_lock lock(mutex_);
      const auto retire = [&] { return running_workers_ > options_.planning_threads; };
      work_cv_.wait(lock, [&] { return stopping_.load() || !queue_.empty() || retire(); });
      if (stopping_) return;
      if (retire()) {
        --running_workers_;
        retired_.push_back(std::this_thread::get_id());
        return;
      }
      job = takeJobLocked();
    }
    planTaken(std::move(job));
  }
}

void Engine::replanLoop() {
  auto next = std::chrono::steady_clock::now();
  while (!stopping_) {
    replanCycle();
    double period_s = 0.1;
    {
      std::lock_guard lock(mutex_);
      period_s = options_.pipeline.replan.period_s;
    }
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(period_s));
    const auto now = std::chrono::steady_clock::now();
    if (next < now) next = now;  // a long cycle: start the next at once rather than catch up
    std::unique_lock lock(mutex_);
    replan_cv_.wait_until(lock, next, [&] { return stopping_.load() || replan_wake_; });
    replan_wake_ = false;
  }
}

void Engine::start() {
  if (running_.exchange(true)) return;
  stopping_ = false;
  int threads = 0;
  {
    std::lock_guard lock(mutex_);
    threads = options_.planning_threads;
    startWorkers(threads);
  }
  replanner_ = std::thread([this] { replanLoop(); });
  spdlog::info("event=engine_started planning_threads={}", threads);
}

void Engine::stop() {
  std::vector<MissionRequestData> dropped;
  std::vector<std::string> dropped_fleets;
  std::vector<std::thread> workers;
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && !running_) return;
    stopping_ = true;
    for (Job* job : in_flight_) job->cancel->store(true);
    for (const auto& [vehicle, mission] : missions_) mission->cancel->store(true);
    for (const auto& [id, fleet] : fleets_) fleet->ended = true;
    for (const auto& job : queue_) {
      if (job->fleet_replan) {
        continue;  // the fleet flies on with the revisions published
      } else if (job->fleet) {
        dropped_fleets.push_back(job->fleet->request_id);
      } else if (!job->resume) {  // a recovered flight's request was answered before the restart
        dropped.push_back(job->request);
      }
    }
    queue_.clear();
    workers = std::move(workers_);
    workers_.clear();
    running_workers_ = 0;
    retired_.clear();
  }
  work_cv_.notify_all();
  replan_cv_.notify_all();
  for (std::thread& t : workers) t.join();
  if (replanner_.joinable()) replanner_.join();
  for (const MissionRequestData& r : dropped) finish(cancelledStatus(r, "the service stopped"));
  for (const std::string& id : dropped_fleets) {
    sink_.publishFleetStatus(fleetFailed(id, PlanError{PlanErrorCode::kCancelled, "", "the service stopped"}));
  }
  throttle_.flushAll();
  if (running_.exchange(false)) spdlog::info("event=engine_stopped");
}

}  // namespace skyroute
