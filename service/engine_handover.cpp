// The engine in a shard group: vehicles handed to another daemon are let go quietly, and vehicles
// taken from one are resumed in flight by the journal restart's path (planResumed). A hot standby
// taking over numbers its revisions on from the primary's.
#include <spdlog/spdlog.h>

#include "service/engine_state.hpp"

namespace skyroute {

void Engine::release(const std::string& vehicle_id) {
  std::vector<std::shared_ptr<Mission>> ended;
  std::size_t dropped = 0;
  std::size_t stopped = 0;
  {
    std::lock_guard lock(mutex_);
    for (auto it = queue_.begin(); it != queue_.end();) {
      if (!(*it)->fleet && (*it)->request.vehicle_id == vehicle_id) {
        // Forgotten, not finished: the vehicle may come back with the same request.
        registry_.abandon(vehicle_id, (*it)->request.request_id);
        it = queue_.erase(it);
        ++dropped;
      } else {
        ++it;
      }
    }
    for (Job* job : in_flight_) {
      if (!job->fleet && job->request.vehicle_id == vehicle_id) {
        job->cancel->store(true);  // its answer is not published: the vehicle is no longer this daemon's
        ++stopped;
      }
    }
    if (auto it = missions_.find(vehicle_id); it != missions_.end()) {
      ended.push_back(it->second);
      missions_.erase(it);
    }
  }
  // Mission locks are never taken under the engine lock (the replanning loop plans under them).
  for (const std::shared_ptr<Mission>& mission : ended) {
    mission->cancel->store(true);
    std::lock_guard mission_lock(mission->mutex);
    mission->ended = true;
  }
  if (dropped + stopped + ended.size() > 0) {
    spdlog::debug("event=vehicle_released vehicle={} queued={} planning={} flying={}", vehicle_id, dropped, stopped,
                  ended.size());
  }
}

void Engine::releaseFleet(const std::string& request_id) {
  std::lock_guard lock(mutex_);
  std::erase_if(queue_, [&](const std::unique_ptr<Job>& job) { return job->fleet && job->fleet->request_id == request_id; });
  for (Job* job : in_flight_) {
    if (job->fleet && job->fleet->request_id == request_id) job->cancel->store(true);
  }
}

void Engine::resumeFlight(const MissionRequestData& request, const TrajectoryData& last,
                          std::int64_t flight_start_utc_ns) {
  auto job = std::make_unique<Job>();
  job->request = request;
  // Without samples the rebuilt flight never equals the published trajectory, so planResumed
  // publishes it at once as the next revision: the readers' last revision came from a writer that
  // is gone or let go, and this daemon's own must follow it.
  TrajectoryData identity;
  identity.vehicle_id = last.vehicle_id;
  identity.plan_id = last.plan_id;
  identity.revision = last.revision;
  identity.request_id = last.request_id;
  identity.created_utc_ns = last.created_utc_ns;
  job->resume = std::move(identity);
  job->resume_start_utc_ns = flight_start_utc_ns;
  {
    std::lock_guard lock(mutex_);
    queue_.push_back(std::move(job));
  }
  work_cv_.notify_one();
}

std::optional<std::uint32_t> Engine::followRevision(const std::string& vehicle_id, const std::string& plan_id,
                                                    std::uint32_t wire_revision) {
  std::shared_ptr<Mission> mission;
  {
    std::lock_guard lock(mutex_);
    auto it = missions_.find(vehicle_id);
    if (it == missions_.end()) return std::nullopt;
    mission = it->second;
  }
  std::lock_guard mission_lock(mission->mutex);
  if (mission->ended || mission->plan_id != plan_id) return std::nullopt;
  const std::uint32_t flight_revision = mission->plan.flight->revision();
  const std::uint32_t current = mission->revision_base + flight_revision;
  if (current == wire_revision || current == wire_revision + 1) return std::nullopt;
  const std::uint32_t next = wire_revision + 1;
  // Unsigned arithmetic wraps: base + flight_revision is `next` even when base "goes below zero"
  // (a standby that made more replans than the primary).
  mission->revision_base = next - flight_revision;
  if (mission->plan.audit_label) mission->plan.audit_label->revision_base = mission->revision_base;
  if (mission->recovered) mission->recovered->revision = next;
  spdlog::info("event=revisions_followed vehicle={} plan={} own_revision={} wire_revision={} revision={}", vehicle_id,
               plan_id, current, wire_revision, next);
  return next;
}

void Engine::setPlanIdTag(const std::string& tag) {
  std::lock_guard lock(mutex_);
  plan_id_tag_ = tag;
}

}  // namespace skyroute
