// skyrouted's node: the engine behind its DDS edge, with an explicit lifecycle as Nav2's managed
// nodes (configure -> activate -> deactivate -> cleanup). Requests, cancels and obstacle updates
// are taken on the node's own thread through a waitset (never in Cyclone's listener threads) and
// only queued there; planning runs on the engine's threads. Trajectories go out reliable,
// transient-local, keep-last 1 per vehicle, so a ground station that joins late gets every
// vehicle's current trajectory; statuses reliable; a ServiceStatus heartbeat every period.
//
// One daemon per service_id and role on a domain: the heartbeat writer names this instance in its
// USER_DATA (service_instance.hpp). activate() first listens for dds.startup_probe_s and refuses
// to start when an older instance serves the same service_id in the same role; one that appears
// later makes the younger of the two stop (on_conflict is called; the daemon exits with a message).
//
// Hot standby (service.role, docs/dds.md): a primary and a standby serve one service_id; both plan
// everything, and the trajectory, status and heartbeat writers are owned (qos.hpp), the primary's
// stronger, so readers take the standby's samples only when the primary's lease runs out. The
// standby then publishes its current trajectories again (readers refused what it wrote before they
// noticed). A primary restarting on its journal first reads the standby's trajectories and
// publishes nothing older than them.
//
// Reload (SIGHUP) validates everything before it changes anything (the DEM is opened, a new DDS
// edge created), and keeps the engine: active missions, their trajectories and the obstacles
// survive. A terrain change is refused while missions are active or requests are waiting.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <shared_mutex>
#include <thread>

#include "service/daemon_config.hpp"
#include "service/dds/ros2_mirror.hpp"
#include "service/dds/service_instance.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/engine.hpp"
#include "service/journaling_sink.hpp"
#include "service/log_throttle.hpp"
#include "service/shard_router.hpp"
#include "service/stall_watch.hpp"
#include "service/state_dir_lock.hpp"
#include "service/state_journal.hpp"

namespace skyroute::dds {

class MissionService final : public EngineSink {
 public:
  enum class State { kUnconfigured, kInactive, kActive };
  // Called (from the node's DDS thread) when this instance must stop for another one; the
  // message says which.
  using ConflictHandler = std::function<void(const std::string& message)>;

  MissionService();
  ~MissionService() override;
  MissionService(const MissionService&) = delete;
  MissionService& operator=(const MissionService&) = delete;

  // Opens the state journal (service.state_dir, when set), loads the terrain, makes the world
  // model and the engine, creates the DDS entities. config.dem_path must be set. Errors name the
  // key or the file (a damaged or newer journal: kParseError naming it).
  Status configure(const DaemonConfig& config);
  // Listens for dds.startup_probe_s for an older instance with this service_id (then fails,
  // naming it: kInvalidArgument "dds.service_id"), then recovers what the journal kept
  // (Engine::recover) and starts the engine and the DDS thread.
  Status activate();
  // Stops the engine first (every plan in progress is cancelled and answered cancelled), then
  // the DDS thread, then waits up to flush_timeout_s in all for readers to acknowledge.
  Status deactivate();
  // Releases the engine, the world and every DDS entity.
  Status cleanup();
  // A new configuration (SIGHUP). Fails, changing nothing, when any part of it cannot be used:
  // an engine option, the DEM, a DDS domain, or a terrain change while missions are active.
  Status reload(const DaemonConfig& config);

  void onConflict(ConflictHandler handler) { on_conflict_ = std::move(handler); }

  State state() const { return state_; }
  DaemonConfig config() const;
  const ServiceInstance& instance() const { return instance_; }
  // The waitset's handle, for a signal handler that only triggers it (WaitLoop::signalStop).
  dds_entity_t waitsetHandle() const;

  // EngineSink: called from the engine's threads.
  void publishStatus(const PlanStatusData& status) override;
  void publishTrajectory(const TrajectoryData& trajectory) override;
  void retractTrajectory(const std::string& vehicle_id) override;
  void publishFleetStatus(const FleetStatusData& status) override;

 private:
  struct Edge;  // the DDS entities of one domain and service_id
  Result<std::unique_ptr<Edge>> makeEdge(const DaemonConfig& config, const WorldModel& world);
  void startDdsThread();
  void stopDdsThread();
  void ddsThread();
  void publishHeartbeat();
  // An older instance with this service_id among the matched heartbeat writers, if any; logs a
  // younger one once.
  std::optional<ServiceInstance> olderRival();
  void checkRivals();  // on a heartbeat writer match: stop for an older rival
  // A standby whose partner's heartbeat writer lost its liveliness: schedules the republishing.
  void checkPartnerLoss();
  void republishDue(std::chrono::steady_clock::time_point now);  // DDS thread
  // An answer addressed to one client (to its cancel, or a refusal of its request) waits until our
  // status writer has matched that client's reader, up to kAnswerWaitS. The client's reader and
  // our writer discover each other separately, and a volatile status written before our side
  // knows the reader is lost to it. A client's answers keep their order.
  static constexpr double kAnswerWaitS = 2.0;
  void answerWhenReachable(const std::string& requester, std::function<void()> answer);  // DDS thread
  void answerReachable(std::chrono::steady_clock::time_point now, bool all);               // DDS thread
  // A standby keeps the primary's last revision of each vehicle from the wire and, taking over,
  // numbers its own on from it (Engine::followRevision) before it republishes.
  void noteWireRevision(const TrajectoryData& trajectory);  // DDS thread
  void followWireRevisions();                               // DDS thread
  // A restarting primary: the journal's trajectories that the standby has since replaced by newer
  // revisions of the same plan are taken from the bus; vehicles it gave a newer plan stay its own.
  void catchUpFromPartner(JournalState& state);

  // Shard groups (service.shard_group, mission_service_shards.cpp). Requests go through the
  // router: every member keeps a copy, the owner plans. Ownership is evaluated again on the
  // DDS thread when a heartbeat writer is matched, leaves or loses its liveliness, and at each
  // heartbeat; vehicles that leave are let go (unregistered) under ownership_mutex_, so no
  // engine thread writes them after.
  static constexpr double kShardJoinMarginS = 1.0;  // a member owns requests that arrive this long after its start
  void startShard();
  void routeMission(MissionRequestData&& request);
  void routeFleet(FleetRequestData&& request);
  bool routeCancel(const CancelRequestData& cancel);  // true: this shard answers it
  // Every request a shard reads is journaled (with --state-dir) before it is routed, so a shard
  // restarted on its journal still has a copy of the others' vehicles (docs/journal.md).
  void journalShardCopy(const JournaledRequest& copy);
  void recoverShardCopies(const std::vector<JournaledRequest>& copies);  // at activate, before the DDS thread
  void recordShardCoverage();  // DDS thread, at each heartbeat: every request read up to a margin ago
  void scheduleShardCheck();                              // DDS thread
  void shardCheckDue(std::chrono::steady_clock::time_point now);  // DDS thread
  void evaluateShard();                                   // DDS thread
  // Runs `decide` (a router call) under ownership_mutex_ and unregisters the trajectories of the
  // vehicles it releases before the lock is let go, so no engine thread writes them after.
  ShardActions decideShard(const std::function<ShardActions()>& decide);
  // Lets go of what `actions` releases (under ownership_mutex_, taken here), then starts what it plans.
  void applyShardActions(const ShardActions& actions);
  // A paused shard (docs/dds.md "A paused shard"). The stall watch notices when this process did
  // not run for longer than kStallFractionOfLease of the liveliness lease: the others may have
  // taken it for dead and taken its vehicles over. From then on it publishes nothing (trajectories,
  // statuses, retractions, fleet statuses) until the DDS thread has begun a new life: every
  // vehicle released, then, after listening again, owning only what a member that joined now would.
  static constexpr double kStallFractionOfLease = 0.5;
  void startStallWatch();
  // cause: "stall" (the watch), or "taken_over" (another daemon published the next revision of a
  // vehicle this one owns; logged as a stall when the watch saw one too). DDS thread.
  void beginShardLife(const std::string& cause);
  // True (and logged, rate-limited) while a stall is suspected: nothing goes out. Engine threads.
  bool fencedByStall(const char* topic, const std::string& key);

  mutable std::mutex config_mutex_;  // config_ (reload writes it, the DDS thread reads it)
  DaemonConfig config_;
  State state_ = State::kUnconfigured;
  ServiceInstance instance_;
  std::shared_ptr<WorldModel> world_;
  std::optional<StateDirLock> state_lock_;         // the state folder's, held with the journal
  std::shared_ptr<StateJournal> journal_;           // null without service.state_dir
  std::unique_ptr<JournalingSink> journal_sink_;    // the engine's sink when journaling: in front of this
  std::optional<JournalState> recovered_;           // what the journal held at configure, until activate
  // The instance that wrote the journal before this one: killed, but discovery lists it until its
  // lease ends; never a rival (two live daemons never share a journal).
  std::string predecessor_instance_id_;
  std::unique_ptr<Engine> engine_;
  // Engine threads publish through the edge while a reload may swap it: shared for publishing,
  // exclusive for the swap.
  mutable std::shared_mutex edge_mutex_;
  std::unique_ptr<Edge> edge_;
  std::thread dds_thread_;
  ConflictHandler on_conflict_;
  bool conflict_reported_ = false;   // DDS thread only
  std::vector<std::string> younger_rivals_logged_;  // DDS thread only
  std::vector<std::string> partners_logged_;        // DDS thread only
  std::uint32_t alive_heartbeat_writers_ = 0;       // DDS thread only
  std::vector<std::chrono::steady_clock::time_point> republish_at_;  // DDS thread only, in order
  struct PendingAnswer {
    std::chrono::steady_clock::time_point give_up_at;  // answered then even if still unreached
    std::string requester;
    std::function<void()> answer;
  };
  std::vector<PendingAnswer> pending_answers_;  // DDS thread only, in arrival order
  struct WireRevision {
    std::string plan_id;
    std::uint32_t revision = 0;
  };
  std::map<std::string, WireRevision> wire_revisions_;  // DDS thread only: a standby's view of the primary's
  bool follow_wire_revisions_ = false;                  // DDS thread only: set by a takeover
  std::set<std::string> renumbered_;                    // DDS thread only: journaled at their republishing
  std::unique_ptr<ShardRouter> router_;  // null unless sharded
  // Publishing (engine threads) holds it shared from the ownership check to the write; a change
  // of ownership holds it exclusive while the released vehicles are unregistered.
  mutable std::shared_mutex ownership_mutex_;
  std::chrono::steady_clock::time_point shard_settle_at_{};          // owns nothing before
  std::vector<std::chrono::steady_clock::time_point> shard_check_at_;  // DDS thread only, in order
  std::vector<std::string> shard_members_logged_;                    // DDS thread only
  bool shard_settled_logged_ = false;                                // DDS thread only
  std::set<std::string> taken_vehicles_;  // DDS thread only: republished with republish_at_
  std::unique_ptr<StallWatch> stall_watch_;  // shards only, from activate()
  std::int64_t life_started_utc_ns_ = 0;     // this life's start (heartbeats, journal); DDS thread after activate
  LogThrottle fence_log_;                    // publications held back, rate-limited per reason and key
  LogThrottle bad_samples_log_;      // refused samples, rate-limited per reason
  std::atomic<std::uint64_t> bad_samples_{0};
};

}  // namespace skyroute::dds
