// One daemon's view of a shard group (docs/dds.md "Shards"): which daemon plans each vehicle, and
// what this daemon must start, resume or let go when requests arrive or members come and go.
// DDS-free: the service's DDS edge feeds it the live members, every request, every cancel and
// the latest trajectory of every vehicle on the wire, and carries out the actions it returns.
//
// The owner of a vehicle is the rendezvous owner (shard_assignment.hpp) of the vehicle's current
// plan: its latest mission request ("vehicle:<id>") or, while a fleet request is its latest plan,
// that fleet ("fleet:<request_id>"), so one daemon plans a whole fleet. Only members that read
// the plan's request can own it (shard_coverage.hpp: serving since at least join_margin before
// it arrived, in this life or in an earlier one their journal kept); when none of them is live
// any more, every live member can. A daemon that joins therefore takes new requests at once, and
// older vehicles only when their owner dies; one restarted on its journal also takes back the
// vehicles of requests it read before, and their owners let go of them.
// What names a vehicle or fleet this daemon never saw a request for (a cancel, a refused request)
// is answered by the oldest live member.
//
// Thread-safe: the edge's thread feeds it, the engine's threads ask who owns what.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "service/mission_types.hpp"
#include "service/shard_coverage.hpp"
#include "service/state_journal.hpp"

namespace skyroute {

struct ShardMember {
  std::string service_id;
  std::int64_t started_utc_ns = 0;
  std::vector<CoverageInterval> past_coverage = {};  // earlier lives kept by its journal
};

// What this daemon knows of a vehicle's trajectory in force, from the wire.
struct PublishedRevision {
  TrajectoryData identity;            // vehicle, plan, revision, request (no samples)
  std::int64_t flight_start_utc_ns = 0;
  std::int64_t end_utc_ns = 0;        // the last sample's time: the flight is over after it
  std::string source_instance;        // the daemon that wrote it (its instance id)
};

struct VehicleMove {
  std::string vehicle_id;
  std::string from;  // service ids; "" = nobody (a new vehicle)
  std::string to;
};

// What the daemon does after a change, in this order: let go, then plan, resume and adopt.
struct ShardActions {
  std::vector<std::string> release_vehicles;  // stop planning and publishing them
  std::vector<std::string> release_fleets;    // fleet requests not to plan any more
  std::vector<MissionRequestData> plan;       // missions to plan from their request
  std::vector<std::pair<MissionRequestData, PublishedRevision>> resume;  // flights to resume
  std::vector<FleetRequestData> plan_fleets;
  std::vector<VehicleMove> moves;             // owners that changed (from or to this daemon, or between others)
  std::vector<std::string> forget_requests;   // copies no longer kept (plan keys): out of the journal too
  bool empty() const {
    return release_vehicles.empty() && release_fleets.empty() && plan.empty() && resume.empty() &&
           plan_fleets.empty() && moves.empty() && forget_requests.empty();
  }
};

class ShardRouter {
 public:
  // self: this daemon's service id and start; self_instance_id: its instance id, which names the
  // trajectories it writes (TrajectoryData::source_instance). Until the first setMembers() with
  // settled = true it owns nothing and plans nothing (the other members are still being discovered).
  ShardRouter(ShardMember self, std::int64_t join_margin_ns, std::string self_instance_id = {});

  // The live members (this daemon is added when missing). settled: this daemon has listened long
  // enough to know them. Returns what moves.
  ShardActions setMembers(std::vector<ShardMember> members, bool settled, std::int64_t now_utc_ns);
  // Every mission and fleet request, on every member, when it arrives.
  ShardActions onMission(const MissionRequestData& request, std::int64_t now_utc_ns);
  ShardActions onFleet(const FleetRequestData& request, std::int64_t now_utc_ns);
  // A cancel: the dormant copy it names is forgotten on every member. True when this daemon
  // answers it (it owns the vehicle, or for a vehicle nobody plans, it is the oldest member).
  bool onCancel(const CancelRequestData& cancel);
  // The copies a journal kept (JournalState::shard_requests), replayed in the order they arrived,
  // each with its arrival time then. Before the first settled setMembers() only: nothing is
  // planned now; the vehicles this daemon owns once settled are resumed from the wire then.
  void recoverRequests(const std::vector<JournaledRequest>& copies);
  // The plan key of a mission's or fleet's copy (the journal's row key).
  static std::string missionKey(const std::string& vehicle_id);
  static std::string fleetKey(const std::string& request_id);

  // A new life of this daemon, started at started_utc_ns (after a stall its peers may have taken
  // for its death; docs/dds.md "A paused shard"): every vehicle and fleet it owned is released,
  // it owns nothing until the next settled setMembers(), and from then on it is a member that
  // joined at started_utc_ns: it has read only the requests that arrive after it, so it takes
  // back none of its old vehicles while a member that read their requests is live.
  ShardActions beginLife(std::int64_t started_utc_ns, std::int64_t now_utc_ns);
  std::int64_t lifeStartedUtcNs() const;

  // Every trajectory another daemon writes (the reader leaves out this daemon's own writer).
  // Returns true when it is another daemon's revision of a vehicle this daemon owns, of the plan
  // this daemon last wrote for it and at least as new: the others took this daemon for dead and
  // took the vehicle over, so what this daemon believes it owns is stale (begin a new life).
  bool onTrajectory(const TrajectoryData& trajectory);
  // Every trajectory this daemon writes, once written.
  void onPublished(const TrajectoryData& trajectory);
  // Whether another daemon's revision of this trajectory's plan on the wire is at least as new:
  // publishing it would make one (plan id, revision) stand for two trajectories, or go back.
  bool supersededOnWire(const TrajectoryData& trajectory) const;

  // Whether this daemon answers for the vehicle (its statuses and trajectories) or the fleet request.
  bool ownsVehicle(const std::string& vehicle_id) const;
  bool ownsFleet(const std::string& request_id) const;
  std::vector<std::string> memberIds() const;  // sorted
  std::size_t ownedVehicles() const;

 private:
  struct Plan {
    std::int64_t seen_utc_ns = 0;
    std::optional<MissionRequestData> mission;  // "vehicle:" keys; empty once cancelled
    std::optional<FleetRequestData> fleet;      // "fleet:" keys
  };
  std::string ownerOfKeyLocked(const std::string& key) const;
  std::string ownerOfVehicleLocked(const std::string& vehicle_id) const;
  // Re-evaluates every vehicle; appends what changed to `actions`.
  void reassignLocked(std::int64_t now_utc_ns, ShardActions& actions);
  // This daemon now owns the vehicle: what to do for it.
  void gainLocked(const std::string& vehicle_id, std::int64_t now_utc_ns, ShardActions& actions,
                  std::set<std::string>& fleets_planned);
  void loseLocked(const std::string& vehicle_id, ShardActions& actions);
  void dropUnusedFleetLocked(const std::string& key, ShardActions& actions);
  bool readLocked(const ShardMember& member, std::int64_t arrived_utc_ns) const;
  // Keeps `revision` as the vehicle's trajectory in force, unless the wire already holds a newer
  // revision of the same plan (samples from two writers may arrive out of order).
  void recordRevisionLocked(PublishedRevision revision);

  mutable std::mutex mutex_;
  ShardMember self_;
  std::int64_t join_margin_ns_;
  std::string self_instance_id_;
  bool settled_ = false;
  std::vector<ShardMember> members_;
  std::map<std::string, Plan> plans_;                    // key -> the plan's request
  std::map<std::string, std::string> vehicle_plan_;      // vehicle -> key of its current plan
  std::map<std::string, std::string> vehicle_owner_;     // vehicle -> owner (service id) as last evaluated
  std::map<std::string, PublishedRevision> published_;   // vehicle -> its trajectory in force
};

}  // namespace skyroute
