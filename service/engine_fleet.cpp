// The engine's fleet requests: queued as any request, planned by the mission pipeline's fleet
// stage on a planning worker, answered with a fleet status and one trajectory per vehicle.
#include <algorithm>
#include <chrono>

#include <spdlog/spdlog.h>

#include "service/engine_state.hpp"

namespace skyroute {

namespace {

FleetStatusData fleetStatus(const std::string& request_id, PlanState state) {
  FleetStatusData s;
  s.request_id = request_id;
  s.state = state;
  return s;
}

}  // namespace

namespace engine_detail {

FleetStatusData fleetFailed(const std::string& request_id, const PlanError& error) {
  FleetStatusData s = fleetStatus(request_id, error.code == PlanErrorCode::kCancelled ? PlanState::kCancelled
                                                                                         : PlanState::kFailed);
  s.error_code = error.code;
  s.field = error.field;
  s.message = error.describe();
  return s;
}

}  // namespace engine_detail

using engine_detail::fleetFailed;

std::optional<PlanError> Engine::submitFleet(FleetRequestData request) {
  auto job = std::make_unique<Job>();
  job->fleet = request;
  const std::optional<PlanError> problem = enqueue(
      std::move(job), [&](const EngineOptions& o) { return checkFleetAdmission(request, o); });
  if (problem) {
    throttle_.warn("fleet_rejected:" + std::string(to_string(problem->code)) + ":" + problem->field,
                   fmt::format("event=fleet_rejected request={} code={} field={} message=\"{}\"", request.request_id,
                               to_string(problem->code), problem->field, problem->message));
    sink_.publishFleetStatus(fleetFailed(request.request_id, *problem));
    return problem;
  }
  spdlog::info("event=fleet_accepted request={} vehicles={} tasks={}", request.request_id, request.vehicle_ids.size(),
               request.tasks.size());
  sink_.publishFleetStatus(fleetStatus(request.request_id, PlanState::kAccepted));
  work_cv_.notify_one();
  return std::nullopt;
}

void Engine::planFleetJob(Job& job) {
  const FleetRequestData& r = *job.fleet;
  if (job.cancel->load()) {
    sink_.publishFleetStatus(fleetFailed(r.request_id, PlanError{PlanErrorCode::kCancelled, "", "cancelled before planning"}));
    return;
  }
  sink_.publishFleetStatus(fleetStatus(r.request_id, PlanState::kPlanning));
  const std::shared_ptr<WorldModel> world_model = world();
  const EngineOptions options = this->options();
  const MissionPipeline pipeline(world_model, options.pipeline);
  TerminationCondition stop;
  stop.withCancelFlag(job.cancel);
  const std::int64_t start_utc_ns = clock_();
  const FleetPlanOutput out = pipeline.planFleet(r, start_utc_ns, stop);
  if (!out.ok()) {
    spdlog::warn("event=fleet_failed request={} code={} field={} message=\"{}\" time_s={:.3f}", r.request_id,
                 to_string(out.status.error_code), out.status.field, out.status.message, out.status.planning_time_s);
    sink_.publishFleetStatus(out.status);
    return;
  }
  // The flying fleet, kept and replanned from here on.
  std::shared_ptr<Fleet> flying;
  if (options.replanning && options.pipeline.fleet_replan.enabled) {
    FleetReplanOptions replan_options = options.pipeline.fleet_replan;
    replan_options.audit = pipeline.fleetAudit(r);  // every revision, as the first ones were
    auto replanner = FleetReplanner::create(r, out, world_model, fleetMissionOptions(options.pipeline), replan_options,
                                            static_cast<double>(start_utc_ns) * 1e-9);
    if (replanner.ok()) {
      flying = std::make_shared<Fleet>();
      flying->request_id = r.request_id;
      flying->replanner = std::move(*replanner);
      flying->changes_checked = world_model->version();
      flying->lands_world_s = static_cast<double>(start_utc_ns) * 1e-9 + out.status.makespan_s;
    } else {
      spdlog::warn("event=fleet_not_replanned request={} message=\"{}\"", r.request_id, replanner.error().describe());
    }
  }
  // A vehicle's own mission ends: the fleet's trajectory replaces it; so does an older fleet that
  // flies one of the vehicles (it is no longer replanned).
  // Decided under the lock, so a stop that began meanwhile is answered cancelled, never succeeded.
  std::vector<std::shared_ptr<Mission>> replaced;
  bool stopped = false;
  std::optional<Error> unrecorded;  // write-ahead: nothing replaced or published without the record
  {
    std::lock_guard lock(mutex_);
    stopped = job.cancel->load() || stopping_;
    if (!stopped) {
      if (Status recorded = sink_.recordFleetPlan(out.trajectories, out.status); !recorded.ok()) unrecorded = recorded.error();
    }
    for (const std::string& vehicle : r.vehicle_ids) {
      if (stopped || unrecorded) break;
      if (auto it = missions_.find(vehicle); it != missions_.end()) {
        replaced.push_back(it->second);
        missions_.erase(it);
      }
      for (auto it = fleets_.begin(); it != fleets_.end();) {
        const std::vector<std::string>& ids = it->second->replanner->request().vehicle_ids;
        if (std::find(ids.begin(), ids.end(), vehicle) != ids.end()) {
          it->second->ended = true;
          it = fleets_.erase(it);
        } else {
          ++it;
        }
      }
    }
    if (!stopped && !unrecorded && flying) {
      if (auto it = fleets_.find(r.request_id); it != fleets_.end()) it->second->ended = true;
      fleets_[r.request_id] = flying;
    }
  }
  if (stopped) {
    sink_.publishFleetStatus(fleetFailed(r.request_id, PlanError{PlanErrorCode::kCancelled, "", "cancelled during planning"}));
    return;
  }
  if (unrecorded) {
    spdlog::warn("event=fleet_not_journaled request={} message=\"{}\"", r.request_id, unrecorded->message);
    sink_.publishFleetStatus(fleetFailed(
        r.request_id, PlanError{PlanErrorCode::kJournalUnavailable, "service.state_dir",
                                "refused: the state journal cannot record the fleet's trajectories (" + unrecorded->message +
                                    "); nothing was published, retry when the journal can write"}));
    return;
  }
  for (const std::shared_ptr<Mission>& m : replaced) {
    m->cancel->store(true);
    std::lock_guard old_lock(m->mutex);
    m->ended = true;
  }
  for (const TrajectoryData& t : out.trajectories) sink_.publishTrajectory(t);
  spdlog::info("event=fleet_succeeded request={} vehicles={} makespan_steps={} makespan_s={:.1f} separation_m={:.0f} "
               "repairs={} time_s={:.3f}",
               r.request_id, r.vehicle_ids.size(), out.status.makespan_steps, out.status.makespan_s,
               out.status.achieved_separation_m, out.status.separation_repairs, out.status.planning_time_s);
  sink_.publishFleetStatus(out.status);
}

void Engine::queueFleetReplans(std::uint64_t changes, double now_s) {
  {
    std::lock_guard lock(mutex_);
    for (auto it = fleets_.begin(); it != fleets_.end();) {
      Fleet& fleet = *it->second;
      if (fleet.ended) {
        it = fleets_.erase(it);
        continue;
      }
      const bool landed = now_s > fleet.lands_world_s;  // its job drops it
      if (fleet.queued || (fleet.changes_checked == changes && !fleet.retry && !landed)) {
        ++it;
        continue;
      }
      // A replan job, ahead of the requests waiting: a flying fleet cannot wait for them.
      fleet.queued = true;
      fleet.changes_checked = changes;
      fleet.retry = false;
      auto job = std::make_unique<Job>();
      job->fleet_replan = it->second;
      queue_.push_front(std::move(job));
      ++it;
    }
  }
  work_cv_.notify_one();
}

void Engine::replanFleetJob(Job& job) {
  Fleet& fleet = *job.fleet_replan;
  const double now_s = static_cast<double>(clock_()) * 1e-9;
  std::vector<TrajectoryData> revisions;
  FleetStatusData status;
  FleetReplanStep step;
  bool answer = false;
  bool finished = false;
  double lands_world_s = 0.0;
  if (!fleet.ended && !job.cancel->load()) {
    std::lock_guard fleet_lock(fleet.mutex);
    TerminationCondition stop;
    stop.withCancelFlag(job.cancel);
    step = fleet.replanner->step(now_s, stop);
    for (std::size_t i : step.changed) revisions.push_back(fleet.replanner->vehicle(i).data);
    status = fleet.replanner->status(step.latency_ms * 1e-3);
    lands_world_s = fleet.replanner->startWorldS() + status.makespan_s;
    finished = fleet.replanner->finished(now_s);
  }
  {
    std::lock_guard lock(mutex_);
    fleet.queued = false;
    fleet.retry = step.unfinished;
    fleet.lands_world_s = lands_world_s;
    // A new allocation is answered; so is a change in the tasks no vehicle can take, and a vehicle
    // left meeting an obstacle (once per change of the world: steps run on changes).
    answer = !revisions.empty() || step.pending.size() != fleet.pending_answered || !step.unresolved.empty();
    fleet.pending_answered = step.pending.size();
    if (finished) {
      fleet.ended = true;
      if (auto it = fleets_.find(fleet.request_id); it != fleets_.end() && it->second.get() == &fleet) fleets_.erase(it);
      spdlog::info("event=fleet_completed request={}", fleet.request_id);
    }
    if (stopping_) return;
  }
  const bool allocation_changed = answer && (status.state == PlanState::kSucceeded || status.state == PlanState::kReplanned);
  if (!revisions.empty() || allocation_changed) {
    if (Status recorded = sink_.recordFleetPlan(revisions, status); !recorded.ok()) {
      // The fleet replanner has moved on to revisions that are not published and cannot be
      // undone: the fleet flies on with the revisions in force and is no longer replanned.
      fleet.ended = true;
      spdlog::warn("event=fleet_replan_not_journaled request={} changed={} message=\"the state journal cannot record "
                   "the fleet's new revisions ({}); the revisions in force stay and the fleet is no longer replanned\"",
                   fleet.request_id, revisions.size(), recorded.error().message);
      return;
    }
  }
  for (const TrajectoryData& t : revisions) sink_.publishTrajectory(t);
  replans_ += revisions.size();
  if (!step.affected.empty() || answer) {
    spdlog::info("event=fleet_replanned request={} affected={} changed={} reallocated={} pending={} candidates={} "
                 "unfinished={} latency_ms={:.1f}",
                 fleet.request_id, step.affected.size(), revisions.size(), step.reallocated.size(), step.pending.size(),
                 step.candidates, step.unfinished, step.latency_ms);
  }
  if (answer) sink_.publishFleetStatus(status);
}

}  // namespace skyroute
