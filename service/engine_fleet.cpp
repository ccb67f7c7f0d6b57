// The engine's fleet requests: queued as any request, planned by the mission pipeline's fleet
// stage on a planning worker, answered with a fleet status and one trajectory per vehicle.
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
      std::move(job), [&](const EngineOptions& o) { return validateFleetRequest(request, fleetMissionOptions(o.pipeline)); });
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
  const MissionPipeline pipeline(world(), options().pipeline);
  TerminationCondition stop;
  stop.withCancelFlag(job.cancel);
  const FleetPlanOutput out = pipeline.planFleet(r, clock_(), stop);
  if (!out.ok()) {
    spdlog::warn("event=fleet_failed request={} code={} field={} message=\"{}\" time_s={:.3f}", r.request_id,
                 to_string(out.status.error_code), out.status.field, out.status.message, out.status.planning_time_s);
    sink_.publishFleetStatus(out.status);
    return;
  }
  // A vehicle's own mission ends: the fleet's trajectory replaces it (and is not replanned).
  // Decided under the lock, so a stop that began meanwhile is answered cancelled, never succeeded.
  std::vector<std::shared_ptr<Mission>> replaced;
  bool stopped = false;
  {
    std::lock_guard lock(mutex_);
    stopped = job.cancel->load() || stopping_;
    for (const std::string& vehicle : r.vehicle_ids) {
      if (stopped) break;
      if (auto it = missions_.find(vehicle); it != missions_.end()) {
        replaced.push_back(it->second);
        missions_.erase(it);
      }
    }
  }
  if (stopped) {
    sink_.publishFleetStatus(fleetFailed(r.request_id, PlanError{PlanErrorCode::kCancelled, "", "cancelled during planning"}));
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

}  // namespace skyroute
