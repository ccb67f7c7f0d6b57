// The ground station of the end-to-end tests and the latency benchmark: a participant of its own
// with every topic skyrouted serves, collecting what arrives.
#pragma once

#include <algorithm>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "service/dds/wait_loop.hpp"

namespace skyroute::testing {

// The ground station: a participant of its own with every topic the daemon serves.
struct Station {
  // Receive time of each trajectory_log entry (steady clock).
  std::vector<std::chrono::steady_clock::time_point> trajectory_times;
  dds::Entity participant;
  std::optional<dds::Writer<MissionRequestData>> requests;
  std::optional<dds::Writer<CancelRequestData>> cancels;
  std::optional<dds::Writer<ObstacleUpdateData>> obstacles;
  std::optional<dds::Reader<PlanStatusData>> statuses;
  std::optional<dds::Reader<TrajectoryData>> trajectories;
  std::optional<dds::Reader<ServiceStatusData>> heartbeat;
  std::optional<dds::Reader<ObstacleUpdateData>> obstacle_echo;
  std::optional<dds::WaitLoop> loop;

  std::vector<PlanStatusData> status_log;
  std::vector<TrajectoryData> trajectory_log;
  std::vector<ObstacleUpdateData> obstacle_log;
  int heartbeats = 0;
  std::vector<std::int64_t> heartbeat_stamps_ns;  // each heartbeat's stamp, as the daemon sent it
  std::optional<ServiceStatusData> last_heartbeat;
  std::map<std::string, ServiceStatusData> heartbeat_of;  // each service_id's last heartbeat

  static std::unique_ptr<Station> open(int domain) {
    auto s = std::make_unique<Station>();
    auto participant = dds::createParticipant(domain);
    if (!participant.ok()) return nullptr;
    s->participant = std::move(*participant);
    const dds_entity_t p = s->participant.get();
    s->requests.emplace(std::move(dds::Writer<MissionRequestData>::create(p).value()));
    s->cancels.emplace(std::move(dds::Writer<CancelRequestData>::create(p).value()));
    s->obstacles.emplace(std::move(dds::Writer<ObstacleUpdateData>::create(p).value()));
    s->statuses.emplace(std::move(dds::Reader<PlanStatusData>::create(p).value()));
    s->trajectories.emplace(std::move(dds::Reader<TrajectoryData>::create(p).value()));
    s->heartbeat.emplace(std::move(dds::Reader<ServiceStatusData>::create(p).value()));
    s->obstacle_echo.emplace(std::move(dds::Reader<ObstacleUpdateData>::create(p).value()));
    s->loop.emplace(std::move(dds::WaitLoop::create(p).value()));
    Station* self = s.get();
    auto ignore = [](const Error&) {};
    (void)s->loop->add(*s->statuses, [self](PlanStatusData&& x) { self->status_log.push_back(std::move(x)); }, ignore);
    (void)s->loop->add(*s->trajectories, [self](TrajectoryData&& x) {
      self->trajectory_log.push_back(std::move(x));
      self->trajectory_times.push_back(std::chrono::steady_clock::now());
    }, ignore);
    (void)s->loop->add(*s->heartbeat, [self](ServiceStatusData&& x) {
      ++self->heartbeats;
      self->heartbeat_stamps_ns.push_back(x.stamp_utc_ns);
      self->heartbeat_of[x.service_id] = x;
      self->last_heartbeat = std::move(x);
    }, ignore);
    (void)s->loop->add(*s->obstacle_echo, [self](ObstacleUpdateData&& x) { self->obstacle_log.push_back(std::move(x)); }, ignore);
    return s;
  }

  // Dispatches samples until done() holds or timeout_s passes; returns done().
  bool pumpUntil(const std::function<bool()>& done, double timeout_s) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (!done()) {
      const double left = std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
      if (left <= 0) return false;
      (void)loop->runOnce(std::min(left, 0.05));
    }
    return true;
  }

  std::optional<PlanStatusData> terminal(const std::string& request_id) const {
    for (const auto& s : status_log)
      if (s.request_id == request_id && isTerminal(s.state)) return s;
    return std::nullopt;
  }
  // Whether request_id has reached `state` (for this station's requests only, when mine).
  bool reached(const std::string& request_id, PlanState state, bool mine = false) const {
    const std::string me = mine ? requesterId() : "";
    return std::any_of(status_log.begin(), status_log.end(), [&](const PlanStatusData& s) {
      return s.request_id == request_id && s.state == state && (!mine || s.requester == me);
    });
  }
  bool waitState(const std::string& request_id, PlanState state, double timeout_s, bool mine = false) {
    return pumpUntil([&] { return reached(request_id, state, mine); }, timeout_s);
  }
  // The GUID the daemon names this station's requests by (PlanStatusData::requester).
  std::string requesterId() const { return dds::entityGuid(requests->handle()); }
  // The final status of request_id addressed to this station (another station may use the id).
  std::optional<PlanStatusData> terminalForMe(const std::string& request_id) const {
    const std::string me = requesterId();
    for (const auto& s : status_log)
      if (s.request_id == request_id && s.requester == me && isTerminal(s.state)) return s;
    return std::nullopt;
  }
  // Waits for the next heartbeat after now, so its counters describe the daemon now.
  std::optional<ServiceStatusData> freshHeartbeat(double timeout_s) {
    const int seen = heartbeats;
    if (!pumpUntil([&] { return heartbeats > seen; }, timeout_s)) return std::nullopt;
    return last_heartbeat;
  }
  bool waitTerminal(const std::vector<std::string>& ids, double timeout_s) {
    return pumpUntil([&] { return std::all_of(ids.begin(), ids.end(), [&](const auto& id) { return terminal(id).has_value(); }); },
                     timeout_s);
  }
  const TrajectoryData* latest(const std::string& vehicle) const {
    const TrajectoryData* found = nullptr;
    for (const auto& t : trajectory_log)
      if (t.vehicle_id == vehicle && (!found || t.revision >= found->revision)) found = &t;
    return found;
  }
  // The trajectory in force for vehicle: the last one received. Unlike latest(), a new plan's
  // revision 0 replaces an older plan's revision 7 (one writer per vehicle delivers in order).
  const TrajectoryData* lastReceived(const std::string& vehicle) const {
    for (auto t = trajectory_log.rbegin(); t != trajectory_log.rend(); ++t)
      if (t->vehicle_id == vehicle) return &*t;
    return nullptr;
  }
};

}  // namespace skyroute::testing
