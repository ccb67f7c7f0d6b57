// The engine after a restart: what the state journal kept (state_journal.hpp) becomes the
// engine's state again, and each flying mission's flight is rebuilt so replanning goes on.
#include <algorithm>
#include <chrono>
#include <map>

#include <spdlog/spdlog.h>

#include "service/engine_state.hpp"
#include "service/no_fly_placement.hpp"
#include "service/state_journal.hpp"

namespace skyroute {

using engine_detail::cancelledStatus;

namespace {

// Whether two trajectories have the same samples (times and positions, bit for bit).
bool sameSamples(const TrajectoryData& a, const TrajectoryData& b) {
  return a.samples.size() == b.samples.size() &&
         std::equal(a.samples.begin(), a.samples.end(), b.samples.begin(), [](const auto& x, const auto& y) {
           return x.t_rel_s == y.t_rel_s && x.position_enu_m == y.position_enu_m;
         });
}

}  // namespace

void Engine::recover(const JournalState& state) {
  std::map<std::string, const TrajectoryData*> trajectory_of;  // vehicle id -> its current trajectory
  for (const TrajectoryData& t : state.trajectories) trajectory_of[t.vehicle_id] = &t;
  std::size_t pending = 0;
  std::size_t resumed = 0;
  {
    std::lock_guard lock(mutex_);
    plan_counter_ = std::max(plan_counter_, state.plan_counter);
    for (const ObstacleUpdateData& update : state.obstacles) world_->apply(update);
    for (const NoFlyZoneData& zone : state.zones) {
      auto checked = placeNoFlyZone(zone, world_->terrain());
      if (!checked.ok()) {
        // A zone that does not fit this terrain (the DEM changed across the restart) is left out.
        spdlog::warn("event=recovery_zone_skipped zone={} message=\"{}\"", zone.zone_id, checked.error().message);
        continue;
      }
      world_->upsertNoFlyZone(std::move(*checked));
    }
    for (const JournalState::Mission& m : state.missions) {
      auto job = std::make_unique<Job>();
      job->request = m.request;
      if (m.flying) {
        auto it = trajectory_of.find(m.request.vehicle_id);
        if (it == trajectory_of.end() || it->second->request_id != m.request.request_id || it->second->samples.empty()) {
          continue;  // its trajectory ended or was replaced
        }
        job->resume = *it->second;
        job->resume_start_utc_ns = m.flight_start_utc_ns != 0 ? m.flight_start_utc_ns : flightStartUtcNs(*it->second);
        ++resumed;
      } else {
        registry_.begin(m.request.vehicle_id, m.request.request_id);
        ++pending;
      }
      queue_.push_back(std::move(job));
    }
  }
  for (const TrajectoryData& t : state.trajectories) {
    // Each is in the journal already, or (a primary that caught up with its standby) on the bus
    // already: recorded again for the latter, and published either way.
    (void)sink_.recordTrajectory(t);
    sink_.publishTrajectory(t);
  }
  for (const FleetStatusData& fleet : state.fleets) sink_.publishFleetStatus(fleet);
  spdlog::info("event=recovered trajectories={} flights_resumed={} missions_replanned={} obstacles={} zones={} "
               "fleets={} plan_counter={}",
               state.trajectories.size(), resumed, pending, state.obstacles.size(), state.zones.size(),
               state.fleets.size(), state.plan_counter);
  work_cv_.notify_all();
}

void Engine::planResumed(Job& job) {
  const auto started = std::chrono::steady_clock::now();
  const MissionRequestData& r = job.request;
  const TrajectoryData& published = *job.resume;
  const EngineOptions options = this->options();
  const std::shared_ptr<WorldModel> world_model = world();
  const MissionPipeline pipeline(world_model, options.pipeline);
  TerminationCondition stop;
  stop.withCancelFlag(job.cancel);
  // The flight starts when its first plan started, so the rebuilt one is timed alike.
  const double start_world_s = static_cast<double>(job.resume_start_utc_ns) * 1e-9;
  auto planned = pipeline.plan(PipelineRequest{r, std::nullopt, std::nullopt}, start_world_s, stop);
  const double time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (!planned.ok() || job.cancel->load()) {
    if (!stopping_ && job.cancel->load()) {  // a cancel of this mission: its trajectory no longer holds
      sink_.retractTrajectory(r.vehicle_id);
      finish(cancelledStatus(r, "cancelled on request"));
      return;
    }
    if (!planned.ok()) {
      // The published trajectory stays; without a flight it is not replanned.
      spdlog::warn("event=resume_failed request={} vehicle={} plan={} field={} message=\"{}\" time_s={:.3f}",
                   r.request_id, r.vehicle_id, published.plan_id, planned.error().field, planned.error().message, time_s);
    }
    return;
  }
  auto mission = std::make_shared<Mission>();
  mission->request = r;
  mission->world_model = world_model;
  mission->plan = std::move(planned.value());
  mission->cancel = job.cancel;
  mission->plan_id = published.plan_id;
  const TrajectoryIdentity identity{r.vehicle_id, published.plan_id, published.revision, r.request_id};
  // The rebuilt flight is what the replanning loop checks from now on. When it is not the
  // published trajectory (that one came from a replan, whose curve the journal does not keep),
  // it goes out as the next revision at once, so what the vehicle flies is what is checked.
  const bool same = sameSamples(pipeline.sample(mission->plan, identity), published);
  mission->revision_base = same ? published.revision : published.revision + 1;
  if (mission->plan.audit_label) mission->plan.audit_label->revision_base = mission->revision_base;
  if (same) mission->recovered = published;
  const TrajectoryData rebuilt = same ? TrajectoryData{} : trajectoryOf(*mission);
  std::unique_lock mission_lock(mission->mutex);
  bool registered = false;
  std::optional<Error> unrecorded;
  {
    std::lock_guard lock(mutex_);
    // A new plan for the vehicle since the restart takes precedence.
    if (!stopping_ && !job.cancel->load() && missions_.find(r.vehicle_id) == missions_.end()) {
      // Write-ahead, under the lock as a new plan's: a rebuilt revision the journal cannot record
      // is not published, and the flight is not kept (the published trajectory stays in force).
      if (!same) {
        if (Status recorded = sink_.recordTrajectory(rebuilt); !recorded.ok()) unrecorded = recorded.error();
      }
      if (!unrecorded) {
        missions_[r.vehicle_id] = mission;
        registered = true;
      }
    }
  }
  if (registered && !same) sink_.publishTrajectory(rebuilt);
  mission_lock.unlock();
  if (unrecorded) {
    spdlog::warn("event=resume_not_journaled request={} vehicle={} plan={} revision={} message=\"the state journal cannot "
                 "record the rebuilt revision ({}); revision {} stays in force and is not replanned\"",
                 r.request_id, r.vehicle_id, published.plan_id, rebuilt.revision, unrecorded->message, published.revision);
  }
  spdlog::info("event=flight_resumed request={} vehicle={} plan={} revision={} registered={} same_samples={} time_s={:.3f}",
               r.request_id, r.vehicle_id, published.plan_id, mission->revision_base, registered, same, time_s);
  replan_cv_.notify_one();
}

}  // namespace skyroute
