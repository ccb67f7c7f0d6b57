// MissionService in a shard group (service.shard_group, docs/dds.md "Shards"): the router
// (shard_router.hpp) says who plans what; this file feeds it from the wire and carries out what
// it decides. Equal ownership strengths: Cyclone's readers settle a tie between two live writers
// of one instance by their GUIDs, not by who wrote last, so a daemon that hands a vehicle to a
// live peer must unregister the instance, or readers could go on refusing the new owner's samples.
// A dead owner needs nothing: its liveliness lease ends its ownership at every reader.
#include <algorithm>
#include <chrono>
#include <optional>

#include <spdlog/spdlog.h>

#include "service/dds/mission_service.hpp"

#include <functional>
#include "service/dds/mission_service_edge.hpp"
#include "service/dds/shard_members.hpp"

namespace skyroute::dds {
namespace {

using Clock = std::chrono::steady_clock;

Clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

std::string joined(const std::vector<std::string>& ids) {
  std::string out;
  for (const std::string& id : ids) out += (out.empty() ? "" : ",") + id;
  return out;
}

}  // namespace

void MissionService::startShard() {
  // Discovery takes a moment: until one lease has passed, the members this daemon sees may not
  // be all there are, so it claims nothing (requests that arrive meanwhile are kept).
  shard_settle_at_ = Clock::now() + seconds(config().liveliness_lease_s);
  shard_check_at_.push_back(shard_settle_at_);
}

void MissionService::scheduleShardCheck() {
  if (!router_) return;
  const auto now = Clock::now();
  // At once, and again shortly: a liveliness change may be signalled before the instance states
  // it changes are readable.
  shard_check_at_.push_back(now);
  shard_check_at_.push_back(now + seconds(0.05));
  std::sort(shard_check_at_.begin(), shard_check_at_.end());
}

void MissionService::shardCheckDue(Clock::time_point now) {
  if (!router_ || shard_check_at_.empty() || now < shard_check_at_.front()) return;
  while (!shard_check_at_.empty() && shard_check_at_.front() <= now) shard_check_at_.erase(shard_check_at_.begin());
  evaluateShard();
}

ShardActions MissionService::decideShard(const std::function<ShardActions()>& decide) {
  std::unique_lock ownership(ownership_mutex_);
  ShardActions actions = decide();
  for (const std::string& vehicle : actions.release_vehicles) {
    TrajectoryData key;
    key.vehicle_id = vehicle;
    (void)edge_->trajectories->unregisterInstance(key);  // an instance never written: nothing to release
  }
  return actions;
}

void MissionService::evaluateShard() {
  std::vector<ShardMember> members;
  for (const ServiceInstance& i : liveShardMembers(edge_->members->handle(), config().shard_group)) {
    members.push_back(ShardMember{i.service_id, i.started_utc_ns, i.past_coverage});
  }
  const bool settled = Clock::now() >= shard_settle_at_;
  const ShardActions actions = decideShard([&] { return router_->setMembers(std::move(members), settled, utcNowNs()); });
  const std::vector<std::string> ids = router_->memberIds();
  if (ids != shard_members_logged_ || settled != shard_settled_logged_) {
    shard_members_logged_ = ids;
    shard_settled_logged_ = settled;
    spdlog::info("event=shard_members group={} members=[{}] self={} settled={}", config().shard_group, joined(ids),
                 instance_.service_id, settled);
  }
  applyShardActions(actions);
}

void MissionService::journalShardCopy(const JournaledRequest& copy) {
  if (!journal_) return;
  // A copy that cannot be written is still routed: this shard may own the vehicle, and its
  // engine's own journal write answers the client; the copy is lost for a restart only.
  if (Status s = journal_->recordShardRequest(copy); !s.ok()) {
    spdlog::warn("event=journal_write_failed what=shard_copy key={} message=\"{}\"", copy.key, s.error().message);
  }
}

void MissionService::recoverShardCopies(const std::vector<JournaledRequest>& copies) {
  router_->recoverRequests(copies);
  spdlog::info("event=shard_copies_recovered requests={} past_lives={}", copies.size(), instance_.past_coverage.size());
}

void MissionService::recordShardCoverage() {
  if (!router_ || !journal_) return;
  // Every request that reached this shard a margin ago has been read and journaled by now
  // (routeMission runs on this thread): the others may count on this shard's copies up to then.
  const auto margin_ns = static_cast<std::int64_t>(kShardJoinMarginS * 1e9);
  if (Status s = journal_->recordShardCoverage(life_started_utc_ns_, utcNowNs() - margin_ns); !s.ok()) {
    spdlog::warn("event=journal_write_failed what=shard_coverage message=\"{}\"", s.error().message);
  }
}

void MissionService::routeMission(MissionRequestData&& request) {
  const std::int64_t now_utc_ns = utcNowNs();
  journalShardCopy(JournaledRequest{ShardRouter::missionKey(request.vehicle_id), now_utc_ns, request, std::nullopt});
  const ShardActions actions = decideShard([&] { return router_->onMission(request, now_utc_ns); });
  if (actions.plan.empty()) {
    spdlog::debug("event=request_dormant request={} vehicle={}", request.request_id, request.vehicle_id);
  }
  applyShardActions(actions);
}

void MissionService::routeFleet(FleetRequestData&& request) {
  const std::int64_t now_utc_ns = utcNowNs();
  journalShardCopy(JournaledRequest{ShardRouter::fleetKey(request.request_id), now_utc_ns, std::nullopt, request});
  const ShardActions actions = decideShard([&] { return router_->onFleet(request, now_utc_ns); });
  applyShardActions(actions);
}

bool MissionService::routeCancel(const CancelRequestData& cancel) {
  if (journal_ && !(cancel.vehicle_id.empty() && cancel.request_id.empty())) {
    if (Status s = journal_->forgetShardMission(cancel.vehicle_id, cancel.request_id); !s.ok()) {
      spdlog::warn("event=journal_write_failed what=shard_cancel request={} vehicle={} message=\"{}\"",
                   cancel.request_id, cancel.vehicle_id, s.error().message);
    }
  }
  return router_->onCancel(cancel);
}

void MissionService::startStallWatch() {
  stall_watch_ = std::make_unique<StallWatch>(config().liveliness_lease_s * kStallFractionOfLease, [this] {
    // The DDS thread begins the new life: wake it now rather than at its next deadline.
    std::shared_lock lock(edge_mutex_);
    if (edge_ && edge_->loop) edge_->loop->wake();
  });
  stall_watch_->start();
}

bool MissionService::fencedByStall(const char* topic, const std::string& key) {
  if (!stall_watch_ || !stall_watch_->suspect()) return false;
  fence_log_.warn(std::string("stall:") + topic,
                  fmt::format("event=publication_fenced topic={} key={} reason=stall message=\"this shard stood still "
                              "for longer than its stall threshold; it publishes nothing before its new life\"",
                              topic, key));
  return true;
}

void MissionService::beginShardLife(const std::string& cause) {
  std::optional<double> paused_s;
  std::int64_t started_utc_ns = 0;
  const std::int64_t now_utc_ns = utcNowNs();
  // Under ownership_mutex_: no engine thread writes between the stall being taken and every
  // vehicle being let go (unregistered).
  const ShardActions actions = decideShard([&] {
    if (stall_watch_) paused_s = stall_watch_->take();
    started_utc_ns = std::max(now_utc_ns, router_->lifeStartedUtcNs() + 1);
    return router_->beginLife(started_utc_ns, now_utc_ns);
  });
  life_started_utc_ns_ = started_utc_ns;
  taken_vehicles_.clear();
  if (journal_) {
    // The life that ended keeps what it last recorded as read; requests read from now on count
    // for the new one (a restart advertises both).
    if (Status s = journal_->beginShardLife(started_utc_ns); !s.ok()) {
      spdlog::warn("event=journal_write_failed what=shard_life message=\"{}\"", s.error().message);
    }
  }
  // It owns nothing until it has listened again for a lease and the longest heartbeat period:
  // its own DDS stack may have let the others' liveliness lapse while it stood still, and their
  // heartbeats make them members again.
  const DaemonConfig c = config();
  double period_s = c.heartbeat_period_s;
  for (const ServiceInstance& i : liveShardMembers(edge_->members->handle(), c.shard_group)) {
    period_s = std::max(period_s, i.heartbeat_period_s);
  }
  const double settle_s = c.liveliness_lease_s + period_s;
  shard_settle_at_ = Clock::now() + seconds(settle_s);
  shard_check_at_.push_back(shard_settle_at_);
  std::sort(shard_check_at_.begin(), shard_check_at_.end());
  // The cause named is the stall whenever the watch saw one, whichever noticed it first.
  spdlog::warn("event=shard_new_life cause={} paused_s={:.2f} released={} life_started_utc_ns={} settle_s={:.2f} "
               "message=\"the other members may have taken this shard for dead: it lets go of every vehicle and "
               "joins again\"",
               paused_s ? "stall" : cause, paused_s.value_or(0.0), actions.release_vehicles.size(), started_utc_ns,
               settle_s);
  applyShardActions(actions);
  publishHeartbeat();  // the others learn of the new life at once
}

void MissionService::applyShardActions(const ShardActions& actions) {
  if (journal_ && !actions.forget_requests.empty()) {
    if (Status s = journal_->forgetShardRequests(actions.forget_requests); !s.ok()) {
      spdlog::warn("event=journal_write_failed what=shard_forget message=\"{}\"", s.error().message);
    }
  }
  for (const std::string& vehicle : actions.release_vehicles) engine_->release(vehicle);
  for (const std::string& request_id : actions.release_fleets) engine_->releaseFleet(request_id);
  for (const MissionRequestData& request : actions.plan) engine_->submit(request);
  for (const auto& [request, last] : actions.resume) {
    engine_->resumeFlight(request, last.identity, last.flight_start_utc_ns);
    taken_vehicles_.insert(request.vehicle_id);
  }
  for (const FleetRequestData& fleet : actions.plan_fleets) engine_->submitFleet(fleet);
  if (!actions.resume.empty()) {
    // Readers that have not yet noticed the old owner's death refuse this daemon's first revision
    // when the old writer wins the tie: once more after a lease, when every reader has.
    republish_at_.push_back(Clock::now() + seconds(config().liveliness_lease_s + 0.1));
    std::sort(republish_at_.begin(), republish_at_.end());
  }
  // Each daemon logs the moves to or from itself; moves from nobody (a daemon settling, a new
  // vehicle) are not moves.
  std::vector<const VehicleMove*> moves;
  for (const VehicleMove& m : actions.moves) {
    if (!m.from.empty() && (m.from == instance_.service_id || m.to == instance_.service_id)) moves.push_back(&m);
  }
  constexpr std::size_t kListed = 8;
  if (moves.size() <= kListed) {
    for (const VehicleMove* m : moves) {
      spdlog::info("event=vehicle_moved vehicle={} from={} to={}", m->vehicle_id, m->from, m->to.empty() ? "-" : m->to);
    }
  } else {
    const auto to_self = std::count_if(moves.begin(), moves.end(),
                                       [&](const VehicleMove* m) { return m->to == instance_.service_id; });
    const auto from_self = std::count_if(moves.begin(), moves.end(),
                                         [&](const VehicleMove* m) { return m->from == instance_.service_id; });
    spdlog::info("event=vehicles_moved count={} to_self={} from_self={}", moves.size(), to_self, from_self);
  }
  if (!actions.resume.empty() || !actions.release_vehicles.empty() || !actions.plan_fleets.empty()) {
    spdlog::info("event=shard_actions released={} planned={} resumed={} fleets_planned={} owned={}",
                 actions.release_vehicles.size(), actions.plan.size(), actions.resume.size(),
                 actions.plan_fleets.size(), router_->ownedVehicles());
  }
}

}  // namespace skyroute::dds
