#include "service/shard_router.hpp"

#include <algorithm>

#include "service/shard_assignment.hpp"
#include "service/state_journal.hpp"

namespace skyroute {
namespace {

constexpr std::string_view kVehiclePrefix = "vehicle:";
constexpr std::string_view kFleetPrefix = "fleet:";

bool isFleetKey(const std::string& key) { return key.rfind(kFleetPrefix, 0) == 0; }

}  // namespace

std::string ShardRouter::missionKey(const std::string& vehicle_id) { return std::string(kVehiclePrefix) + vehicle_id; }
std::string ShardRouter::fleetKey(const std::string& request_id) { return std::string(kFleetPrefix) + request_id; }

bool ShardRouter::readLocked(const ShardMember& member, std::int64_t arrived_utc_ns) const {
  return coversArrival(member.started_utc_ns, member.past_coverage, arrived_utc_ns, join_margin_ns_);
}

ShardRouter::ShardRouter(ShardMember self, std::int64_t join_margin_ns, std::string self_instance_id)
    : self_(std::move(self)),
      join_margin_ns_(join_margin_ns),
      self_instance_id_(std::move(self_instance_id)),
      members_{self_} {}

std::string ShardRouter::ownerOfKeyLocked(const std::string& key) const {
  if (!settled_) return {};
  auto plan = plans_.find(key);
  if (plan == plans_.end()) {
    // A key this daemon never saw a request for (a cancel or a refused request naming an unknown
    // vehicle): the oldest member answers. It has read every request any younger member read,
    // so it knows the key when anyone does, and then this daemon's answer is "not mine" too.
    const auto oldest = std::min_element(members_.begin(), members_.end(), [](const auto& a, const auto& b) {
      return a.started_utc_ns != b.started_utc_ns ? a.started_utc_ns < b.started_utc_ns : a.service_id < b.service_id;
    });
    return oldest->service_id;
  }
  std::vector<std::string> eligible;
  // Members that were serving when the request arrived read it too; a later joiner, or one that
  // was down then, may not have.
  for (const ShardMember& m : members_) {
    if (readLocked(m, plan->second.seen_utc_ns)) eligible.push_back(m.service_id);
  }
  if (eligible.empty()) {
    for (const ShardMember& m : members_) eligible.push_back(m.service_id);
  }
  return rendezvousOwner(eligible, key);
}

std::string ShardRouter::ownerOfVehicleLocked(const std::string& vehicle_id) const {
  if (auto owner = vehicle_owner_.find(vehicle_id); owner != vehicle_owner_.end()) return owner->second;
  return ownerOfKeyLocked(missionKey(vehicle_id));
}

ShardActions ShardRouter::setMembers(std::vector<ShardMember> members, bool settled, std::int64_t now_utc_ns) {
  members.push_back(self_);
  // One entry per service id: a restarted daemon's old instance may still be listed; the newest counts.
  std::sort(members.begin(), members.end(), [](const ShardMember& a, const ShardMember& b) {
    return a.service_id != b.service_id ? a.service_id < b.service_id : a.started_utc_ns > b.started_utc_ns;
  });
  members.erase(std::unique(members.begin(), members.end(),
                            [](const ShardMember& a, const ShardMember& b) { return a.service_id == b.service_id; }),
                members.end());
  std::lock_guard lock(mutex_);
  ShardActions actions;
  const bool same = members.size() == members_.size() &&
                    std::equal(members.begin(), members.end(), members_.begin(), [](const auto& a, const auto& b) {
                      return a.service_id == b.service_id && a.started_utc_ns == b.started_utc_ns;
                    });
  if (same && (settled_ || !settled)) return actions;
  members_ = std::move(members);
  settled_ = settled_ || settled;
  reassignLocked(now_utc_ns, actions);
  return actions;
}

void ShardRouter::reassignLocked(std::int64_t now_utc_ns, ShardActions& actions) {
  std::set<std::string> fleets_planned;
  for (const auto& [vehicle, key] : vehicle_plan_) {
    const std::string owner = ownerOfKeyLocked(key);
    std::string& known = vehicle_owner_[vehicle];
    if (owner == known) continue;
    actions.moves.push_back(VehicleMove{vehicle, known, owner});
    if (known == self_.service_id) loseLocked(vehicle, actions);
    known = owner;
    if (owner == self_.service_id) gainLocked(vehicle, now_utc_ns, actions, fleets_planned);
  }
}

void ShardRouter::gainLocked(const std::string& vehicle_id, std::int64_t now_utc_ns, ShardActions& actions,
                             std::set<std::string>& fleets_planned) {
  const std::string& key = vehicle_plan_.at(vehicle_id);
  const Plan& plan = plans_.at(key);
  if (plan.fleet) {
    const FleetRequestData& fleet = *plan.fleet;
    if (!fleets_planned.insert(fleet.request_id).second) return;
    // Planned already when any of its trajectories is on the wire: the engine never replans a
    // fleet's vehicles, so there is nothing to resume; its trajectories stay with the readers.
    for (const std::string& v : fleet.vehicle_ids) {
      auto p = published_.find(v);
      if (p != published_.end() && p->second.identity.request_id == fleet.request_id) return;
    }
    actions.plan_fleets.push_back(fleet);
    return;
  }
  if (!plan.mission) return;  // cancelled
  auto p = published_.find(vehicle_id);
  if (p == published_.end() || p->second.identity.request_id != plan.mission->request_id) {
    actions.plan.push_back(*plan.mission);  // never planned, or still being planned by the old owner
  } else if (p->second.end_utc_ns > now_utc_ns) {
    actions.resume.emplace_back(*plan.mission, p->second);
  }
  // else: its flight is over; nothing to plan.
}

void ShardRouter::loseLocked(const std::string& vehicle_id, ShardActions& actions) {
  actions.release_vehicles.push_back(vehicle_id);
  const std::string& key = vehicle_plan_.at(vehicle_id);
  if (isFleetKey(key)) {
    const std::string request_id = key.substr(kFleetPrefix.size());
    if (std::find(actions.release_fleets.begin(), actions.release_fleets.end(), request_id) ==
        actions.release_fleets.end()) {
      actions.release_fleets.push_back(request_id);
    }
  }
}

void ShardRouter::dropUnusedFleetLocked(const std::string& key, ShardActions& actions) {
  for (const auto& [vehicle, current] : vehicle_plan_) {
    if (current == key) return;
  }
  plans_.erase(key);
  actions.forget_requests.push_back(key);
}

ShardActions ShardRouter::onMission(const MissionRequestData& request, std::int64_t now_utc_ns) {
  std::lock_guard lock(mutex_);
  ShardActions actions;
  const std::string key = missionKey(request.vehicle_id);
  plans_[key] = Plan{now_utc_ns, request, std::nullopt};
  std::string& current = vehicle_plan_[request.vehicle_id];
  const std::string previous_key = current;
  current = key;
  if (previous_key != key && isFleetKey(previous_key)) dropUnusedFleetLocked(previous_key, actions);
  const std::string owner = ownerOfKeyLocked(key);
  std::string& known = vehicle_owner_[request.vehicle_id];
  if (owner != known) {
    if (!known.empty()) actions.moves.push_back(VehicleMove{request.vehicle_id, known, owner});
    if (known == self_.service_id) actions.release_vehicles.push_back(request.vehicle_id);
    known = owner;
  }
  if (owner == self_.service_id) actions.plan.push_back(request);
  return actions;
}

ShardActions ShardRouter::onFleet(const FleetRequestData& request, std::int64_t now_utc_ns) {
  std::lock_guard lock(mutex_);
  ShardActions actions;
  const std::string key = fleetKey(request.request_id);
  plans_[key] = Plan{now_utc_ns, std::nullopt, request};
  const std::string owner = ownerOfKeyLocked(key);
  for (const std::string& vehicle : request.vehicle_ids) {
    std::string& current = vehicle_plan_[vehicle];
    const std::string previous_key = current;
    current = key;
    if (previous_key != key && isFleetKey(previous_key)) dropUnusedFleetLocked(previous_key, actions);
    std::string& known = vehicle_owner_[vehicle];
    if (owner == known) continue;
    if (!known.empty()) actions.moves.push_back(VehicleMove{vehicle, known, owner});
    if (known == self_.service_id) actions.release_vehicles.push_back(vehicle);
    known = owner;
  }
  if (owner == self_.service_id) actions.plan_fleets.push_back(request);
  return actions;
}

bool ShardRouter::onCancel(const CancelRequestData& cancel) {
  std::lock_guard lock(mutex_);
  std::string vehicle = cancel.vehicle_id;
  if (vehicle.empty()) {
    for (const auto& [v, key] : vehicle_plan_) {
      const Plan& plan = plans_.at(key);
      if (plan.mission && plan.mission->request_id == cancel.request_id) vehicle = v;
    }
  }
  if (vehicle.empty()) return settled_ && ownerOfKeyLocked("request:" + cancel.request_id) == self_.service_id;
  if (auto current = vehicle_plan_.find(vehicle); current != vehicle_plan_.end()) {
    Plan& plan = plans_.at(current->second);
    if (plan.mission && (cancel.request_id.empty() || plan.mission->request_id == cancel.request_id)) {
      plan.mission.reset();  // never resumed or planned again by whoever owns the vehicle next
    }
  }
  return settled_ && ownerOfVehicleLocked(vehicle) == self_.service_id;
}

void ShardRouter::recoverRequests(const std::vector<JournaledRequest>& copies) {
  for (const JournaledRequest& copy : copies) {
    if (copy.mission) (void)onMission(*copy.mission, copy.seen_utc_ns);
    if (copy.fleet) (void)onFleet(*copy.fleet, copy.seen_utc_ns);
  }
}

namespace {

PublishedRevision revisionOf(const TrajectoryData& trajectory, const std::string& source_instance) {
  PublishedRevision p;
  p.identity.vehicle_id = trajectory.vehicle_id;
  p.identity.plan_id = trajectory.plan_id;
  p.identity.revision = trajectory.revision;
  p.identity.request_id = trajectory.request_id;
  p.identity.created_utc_ns = trajectory.created_utc_ns;
  p.flight_start_utc_ns = flightStartUtcNs(trajectory);
  p.end_utc_ns = trajectory.samples.back().utc_ns;
  p.source_instance = source_instance;
  return p;
}

}  // namespace

void ShardRouter::recordRevisionLocked(PublishedRevision revision) {
  PublishedRevision& kept = published_[revision.identity.vehicle_id];
  if (kept.identity.plan_id == revision.identity.plan_id && kept.identity.revision > revision.identity.revision) return;
  kept = std::move(revision);
}

bool ShardRouter::onTrajectory(const TrajectoryData& trajectory) {
  if (trajectory.samples.empty()) return false;
  PublishedRevision p = revisionOf(trajectory, trajectory.source_instance);
  std::lock_guard lock(mutex_);
  bool taken_over = false;
  if (settled_ && !self_instance_id_.empty() && trajectory.source_instance != self_instance_id_) {
    const auto mine = published_.find(trajectory.vehicle_id);
    const auto owner = vehicle_owner_.find(trajectory.vehicle_id);
    taken_over = mine != published_.end() && mine->second.source_instance == self_instance_id_ &&
                 mine->second.identity.plan_id == trajectory.plan_id &&
                 trajectory.revision >= mine->second.identity.revision && owner != vehicle_owner_.end() &&
                 owner->second == self_.service_id;
  }
  recordRevisionLocked(std::move(p));
  return taken_over;
}

void ShardRouter::onPublished(const TrajectoryData& trajectory) {
  if (trajectory.samples.empty()) return;
  PublishedRevision p = revisionOf(trajectory, self_instance_id_);
  std::lock_guard lock(mutex_);
  recordRevisionLocked(std::move(p));
}

bool ShardRouter::supersededOnWire(const TrajectoryData& trajectory) const {
  std::lock_guard lock(mutex_);
  const auto wire = published_.find(trajectory.vehicle_id);
  return wire != published_.end() && wire->second.source_instance != self_instance_id_ &&
         wire->second.identity.plan_id == trajectory.plan_id && wire->second.identity.revision >= trajectory.revision;
}

ShardActions ShardRouter::beginLife(std::int64_t started_utc_ns, std::int64_t now_utc_ns) {
  std::lock_guard lock(mutex_);
  ShardActions actions;
  self_.started_utc_ns = started_utc_ns;
  for (ShardMember& m : members_) {
    if (m.service_id == self_.service_id) m = self_;
  }
  // Unsettled, it owns nothing: every vehicle it owned moves away from it now (to nobody, as far
  // as it knows, until it has listened to the others again).
  settled_ = false;
  reassignLocked(now_utc_ns, actions);
  return actions;
}

std::int64_t ShardRouter::lifeStartedUtcNs() const {
  std::lock_guard lock(mutex_);
  return self_.started_utc_ns;
}

bool ShardRouter::ownsVehicle(const std::string& vehicle_id) const {
  std::lock_guard lock(mutex_);
  return settled_ && ownerOfVehicleLocked(vehicle_id) == self_.service_id;
}

bool ShardRouter::ownsFleet(const std::string& request_id) const {
  std::lock_guard lock(mutex_);
  return settled_ && ownerOfKeyLocked(fleetKey(request_id)) == self_.service_id;
}

std::vector<std::string> ShardRouter::memberIds() const {
  std::lock_guard lock(mutex_);
  std::vector<std::string> ids;
  for (const ShardMember& m : members_) ids.push_back(m.service_id);
  return ids;
}

std::size_t ShardRouter::ownedVehicles() const {
  std::lock_guard lock(mutex_);
  return static_cast<std::size_t>(std::count_if(vehicle_owner_.begin(), vehicle_owner_.end(),
                                                [&](const auto& entry) { return entry.second == self_.service_id; }));
}

}  // namespace skyroute
