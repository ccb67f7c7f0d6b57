#include "service/dds/mission_service.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>

#include <spdlog/spdlog.h>

#include "service/dds/mission_service_edge.hpp"
#include "service/dds/shard_members.hpp"
#include "service/journal_schema.hpp"
#include "service/journal_screening.hpp"
#include "service/no_fly_geojson.hpp"

namespace skyroute::dds {
namespace {

// Moves what a create call made into its place in the edge; the creation's error otherwise.
template <class T>
std::optional<Error> emplaceCreated(std::optional<T>& member, Result<T> created) {
  if (!created.ok()) return created.error();
  member.emplace(std::move(*created));
  return std::nullopt;
}

// The IDL revision of idl/skyroute.idl: bump when a message changes incompatibly.
constexpr const char* kIdlVersion = "skyroute_msgs/4";

using Clock = std::chrono::steady_clock;

Clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

// The terrain and world model of a configuration; errors name the DEM.
Result<std::shared_ptr<WorldModel>> loadWorld(const DaemonConfig& config) {
  if (config.dem_path.empty()) return make_error(ErrorCode::kInvalidArgument, "terrain.dem", "no DEM path");
  auto world = WorldModel::load(config.dem_path, config.world);
  if (!world.ok()) {
    Error e = world.error();
    e.field = "terrain.dem";
    e.message = config.dem_path + ": " + e.message;
    return e;
  }
  if (!config.nofly_path.empty()) {
    auto zones = loadNoFlyGeoJson(config.nofly_path, (*world)->frame(), &(*world)->terrain());
    if (!zones.ok()) return make_error(zones.error().code, "terrain.nofly", zones.error().describe());
    spdlog::info("event=nofly_zones_loaded file={} zones={}", config.nofly_path, zones->size());
    (*world)->setNoFlyZones(std::move(*zones));
  }
  return world;
}

bool terrainChanged(const DaemonConfig& a, const DaemonConfig& b) {
  return a.dem_path != b.dem_path || a.nofly_path != b.nofly_path || a.world.vehicle_radius_m != b.world.vehicle_radius_m ||
         a.world.terrain_margin_m != b.world.terrain_margin_m ||
         a.world.constant_velocity_horizon_s != b.world.constant_velocity_horizon_s;
}

// The DDS entities are made anew: another domain, service id or security identity, or another
// ROS 2 mirror (on or off, or the origin of another terrain).
bool edgeChanged(const DaemonConfig& a, const DaemonConfig& b) {
  return a.domain != b.domain || a.service_id != b.service_id || a.security_dir != b.security_dir ||
         a.role != b.role || a.shard_group != b.shard_group || a.primary_strength != b.primary_strength || a.standby_strength != b.standby_strength ||
         a.liveliness_lease_s != b.liveliness_lease_s ||
         a.ros2_enabled != b.ros2_enabled ||
         (b.ros2_enabled && terrainChanged(a, b));
}

}  // namespace


MissionService::MissionService() = default;

MissionService::~MissionService() {
  (void)deactivate();
  (void)cleanup();
}

DaemonConfig MissionService::config() const {
  std::lock_guard lock(config_mutex_);
  return config_;
}

dds_entity_t MissionService::waitsetHandle() const {
  std::shared_lock lock(edge_mutex_);
  return edge_ && edge_->loop ? edge_->loop->waitsetHandle() : 0;
}

Result<std::unique_ptr<MissionService::Edge>> MissionService::makeEdge(const DaemonConfig& config,
                                                                      const WorldModel& world) {
  auto edge = std::make_unique<Edge>();
  edge->domain = config.domain;
  ServiceInstance me = instance_;
  me.service_id = config.service_id;
  me.heartbeat_period_s = config.heartbeat_period_s;
  me.role = config.role;
  me.shard_group = config.shard_group;
  const OwnedWriterOptions owned{ownershipStrength(config), config.liveliness_lease_s};
  // A participant's announcement travels in clear even under DDS Security (the specification's
  // SPDP), so a secured daemon names itself only in its heartbeat writer's USER_DATA, which secure
  // discovery encrypts; peers then learn of it at endpoint discovery instead of participant discovery.
  const std::string participant_data = config.security_dir.empty() ? me.userData() : std::string();
  auto participant = createParticipant(static_cast<dds_domainid_t>(config.domain), participant_data, config.security_dir);
  if (!participant.ok()) {
    Error e = participant.error();
    if (config.security_dir.empty()) {
      e.field = "dds.domain";
    } else {
      e.message = e.describe();
      e.field = "security.dir";
    }
    return e;
  }
  edge->participant = std::move(*participant);
  const dds_entity_t p = edge->participant.get();

  if (auto e = emplaceCreated(edge->requests, Reader<MissionRequestData>::create(p))) return *e;
  if (auto e = emplaceCreated(edge->cancels, Reader<CancelRequestData>::create(p))) return *e;
  if (auto e = emplaceCreated(edge->obstacles, Reader<ObstacleUpdateData>::create(p))) return *e;
  if (auto e = emplaceCreated(edge->zones, Reader<NoFlyZoneData>::create(p))) return *e;
  // The owned writers name this instance too, so a ground station can tell which daemon it hears.
  if (auto e = emplaceCreated(edge->trajectories, Writer<TrajectoryData>::create(p, me.userData(), owned))) return *e;
  if (auto e = emplaceCreated(edge->statuses, Writer<PlanStatusData>::create(p, me.userData(), owned))) return *e;
  if (auto e = emplaceCreated(edge->heartbeat, Writer<ServiceStatusData>::create(p, me.userData(), owned))) return *e;
  if (auto e = emplaceCreated(edge->rivals, Reader<ServiceStatusData>::create(p))) return *e;
  if (auto e = emplaceCreated(edge->fleet_requests, Reader<FleetRequestData>::create(p))) return *e;
  if (auto e = emplaceCreated(edge->fleet_statuses, Writer<FleetStatusData>::create(p, me.userData(), owned))) return *e;
  if (!config.shard_group.empty()) {
    if (auto e = emplaceCreated(edge->members, Reader<ServiceStatusData>::create(p))) return *e;
  }
  // Shards follow every vehicle's last revision on the wire; a standby the primary's.
  // A shard's reader leaves out its own writer: with equal strengths, its own live writer could
  // win the tie at its reader and hide another daemon's revisions of a vehicle it wrote (the
  // router takes this daemon's own trajectories from publishTrajectory instead).
  if (!config.shard_group.empty() || config.role == "standby") {
    const bool ignore_own = !config.shard_group.empty();
    if (auto e = emplaceCreated(edge->published, Reader<TrajectoryData>::create(p, ignore_own))) return *e;
  }
  if (config.ros2_enabled) edge->ros2 = Ros2Mirror::create(p, world.frame().anchor());
  if (auto e = emplaceCreated(edge->loop, WaitLoop::create(p))) return *e;

  // Handlers only queue or flag: planning happens on the engine's threads. A refused sample is
  // logged (rate-limited per reason) and answered where its topic has a reply.
  WaitLoop& l = *edge->loop;
  Status added = l.addWithRejects(
      *edge->requests,
      [this](MissionRequestData&& request) {
        if (router_) {
          routeMission(std::move(request));
        } else {
          engine_->submit(std::move(request));
        }
      },
      [this](const Error& e, const MissionRequestData& identity) {
        ++bad_samples_;
        bad_samples_log_.warn("bad_request:" + e.field,
                              fmt::format("event=bad_request request={} vehicle={} field={} message=\"{}\"",
                                          identity.request_id, identity.vehicle_id, e.field, e.message));
        const PlanStatusData refusal = PlanStatusData::failed(identity, toPlanError(e), 0.0);
        answerWhenReachable(identity.requester, [this, refusal] { publishStatus(refusal); });
      });
  if (!added.ok()) return added.error();
  added = l.addWithRejects(
      *edge->cancels,
      [this](CancelRequestData&& cancel) {
        const std::string requester = cancel.requester;
        answerWhenReachable(requester, [this, cancel = std::move(cancel)] {
          // In a shard group only the vehicle's owner answers; every member forgets the mission.
          if (!router_ || routeCancel(cancel)) engine_->cancel(cancel);
        });
      },
      [this](const Error& e, const CancelRequestData& identity) {
        ++bad_samples_;
        bad_samples_log_.warn("bad_cancel:" + e.field, fmt::format("event=bad_cancel request={} vehicle={} field={} "
                                                                   "message=\"{}\"",
                                                                   identity.request_id, identity.vehicle_id, e.field,
                                                                   e.message));
        if (identity.request_id.empty() && identity.vehicle_id.empty()) return;  // nobody to answer
        MissionRequestData who;
        who.request_id = identity.request_id;
        who.vehicle_id = identity.vehicle_id;
        who.requester = identity.requester;
        const PlanStatusData refusal = PlanStatusData::failed(who, toPlanError(e), 0.0);
        answerWhenReachable(identity.requester, [this, refusal] { publishStatus(refusal); });
      });
  if (!added.ok()) return added.error();
  // A refused obstacle or zone has no reply topic: counted and logged (rate-limited per field).
  const auto logBad = [this](const char* event) {
    return [this, event](const Error& e) {
      ++bad_samples_;
      bad_samples_log_.warn(std::string(event) + ":" + e.field,
                            fmt::format("event={} field={} message=\"{}\"", event, e.field, e.message));
    };
  };
  added = l.add(*edge->obstacles, [this](ObstacleUpdateData&& update) { engine_->updateObstacle(update); },
                logBad("bad_obstacle_update"));
  if (!added.ok()) return added.error();
  added = l.add(*edge->zones, [this](NoFlyZoneData&& zone) { engine_->updateNoFlyZone(zone); },
                logBad("bad_nofly_zone"));
  if (!added.ok()) return added.error();
  // Heartbeat samples carry nothing the node needs (rivals are read from discovery): drained.
  added = l.add(*edge->rivals, [](ServiceStatusData&&) {}, [](const Error&) {});
  if (!added.ok()) return added.error();
  // A heartbeat writer that appears may be a rival; one that loses its liveliness (killed) or goes
  // away may be the primary this standby stands in for.
  added = l.addStatus(edge->rivals->handle(), DDS_SUBSCRIPTION_MATCHED_STATUS | DDS_LIVELINESS_CHANGED_STATUS, [this] {
    checkRivals();
    checkPartnerLoss();
  });
  if (!added.ok()) return added.error();
  added = l.addWithRejects(
      *edge->fleet_requests,
      [this](FleetRequestData&& request) {
        if (router_) {
          routeFleet(std::move(request));
        } else {
          engine_->submitFleet(std::move(request));
        }
      },
      [this](const Error& e, const FleetRequestData& identity) {
        ++bad_samples_;
        bad_samples_log_.warn("bad_fleet_request:" + e.field,
                              fmt::format("event=bad_fleet_request request={} field={} message=\"{}\"",
                                          identity.request_id, e.field, e.message));
        const PlanError error = toPlanError(e);
        FleetStatusData status;
        status.request_id = identity.request_id;
        status.state = PlanState::kFailed;
        status.error_code = error.code;
        status.field = error.field;
        status.message = error.describe();
        publishFleetStatus(status);
      });
  if (!added.ok()) return added.error();
  if (edge->members) {
    // A member that appears, leaves or loses its liveliness (killed): the vehicles are assigned
    // again. Its samples stay in the reader (read, never taken), so only its statuses wake the loop.
    added = l.addStatus(edge->members->handle(), DDS_SUBSCRIPTION_MATCHED_STATUS | DDS_LIVELINESS_CHANGED_STATUS,
                        [this] { scheduleShardCheck(); });
    if (!added.ok()) return added.error();
  }
  if (edge->published) {
    added = l.add(
        *edge->published,
        [this](TrajectoryData&& t) {
          if (router_) {
            if (router_->onTrajectory(t)) {
              spdlog::warn("event=shard_taken_over vehicle={} plan={} revision={} by={} message=\"another daemon "
                           "published the next revision of a vehicle this shard owns: it was taken for dead\"",
                           t.vehicle_id, t.plan_id, t.revision, t.source_instance);
              beginShardLife("taken_over");
            }
          } else {
            noteWireRevision(t);
          }
        },
        [](const Error&) {});
    if (!added.ok()) return added.error();
  }
  return edge;
}

Status MissionService::configure(const DaemonConfig& config) {
  if (state_ != State::kUnconfigured) {
    return make_error(ErrorCode::kInvalidArgument, "lifecycle", "configure needs the unconfigured state");
  }
  const auto started = Clock::now();
  instance_ = ServiceInstance::current(config.service_id, config.heartbeat_period_s, config.role);
  if (!config.state_dir.empty()) {  // first: a refused journal stops the start before the DEM loads
    std::error_code made;
    std::filesystem::create_directories(config.state_dir, made);
    // One daemon per folder, held until cleanup() (or the process's end, kill -9 included).
    auto lock = StateDirLock::acquire(config.state_dir, instance_.instance_id, instance_.started_utc_ns);
    if (!lock.ok()) return lock.error();
    state_lock_.emplace(std::move(*lock));
    auto journal = StateJournal::open(config.state_dir);
    if (!journal.ok()) return journal.error();
    auto state = (*journal)->load(utcNowNs());
    if (!state.ok()) return state.error();
    spdlog::info("event=journal_opened path={} schema_found={} schema={} missions={} trajectories={} obstacles={} "
                 "zones={} damaged={}",
                 (*journal)->path(), (*journal)->foundSchemaVersion(), kJournalSchemaVersion, state->missions.size(),
                 state->trajectories.size(), state->obstacles.size(), state->zones.size(), state->quarantined.size());
    journal_ = std::move(*journal);
    journal_sink_ = std::make_unique<JournalingSink>(*this, journal_);
    recovered_ = std::move(*state);
  }
  auto world = loadWorld(config);
  if (!world.ok()) return world.error();
  if (recovered_) {
    // Nothing is replayed that a new request would be refused today (the bounds in force, this
    // terrain): such records are quarantined, logged by key, and the rest resumes.
    const std::vector<QuarantinedRecord> refused = screenJournalState(*recovered_, config.engine, **world);
    (void)journal_->quarantine(refused, utcNowNs());
    recovered_->quarantined.insert(recovered_->quarantined.end(), refused.begin(), refused.end());
  }
  auto engine = Engine::create(*world, config.engine, journal_sink_ ? static_cast<EngineSink&>(*journal_sink_) : *this);
  if (!engine.ok()) return engine.error();
  instance_.shard_group = config.shard_group;
  life_started_utc_ns_ = instance_.started_utc_ns;
  if (!config.shard_group.empty()) {
    const auto margin_ns = static_cast<std::int64_t>(kShardJoinMarginS * 1e9);
    if (journal_) {
      // The journal's earlier lives tell the others which older requests this shard read.
      instance_.past_coverage = advertisedCoverage(recovered_->shard_lives, margin_ns);
      if (Status s = journal_->beginShardLife(instance_.started_utc_ns); !s.ok()) return s.error();
    }
    router_ = std::make_unique<ShardRouter>(
        ShardMember{config.service_id, instance_.started_utc_ns, instance_.past_coverage}, margin_ns,
        instance_.instance_id);
    // Shards plan the same vehicles in turn, each counting its own plans: its instance in the plan id.
    (*engine)->setPlanIdTag(instance_.instance_id.substr(0, 8));
  }
  if (journal_) {
    predecessor_instance_id_ = recovered_->owner_instance_id;
    if (Status s = journal_->recordOwner(instance_.instance_id); !s.ok()) {
      // A journal that cannot write (a full disk) is still recovered; new work is refused.
      spdlog::error("event=journal_write_failed what=owner message=\"{}\"", s.error().message);
    }
  }
  bad_samples_log_.setWindowS(config.engine.log_repeat_window_s);
  fence_log_.setWindowS(config.engine.log_repeat_window_s);
  auto edge = makeEdge(config, **world);
  if (!edge.ok()) return edge.error();

  {
    std::lock_guard lock(config_mutex_);
    config_ = config;
  }
  world_ = std::move(*world);
  engine_ = std::move(*engine);
  {
    std::unique_lock lock(edge_mutex_);
    edge_ = std::move(*edge);
  }
  state_ = State::kInactive;
  spdlog::info("event=configured dem={} domain={} instance={} time_s={:.2f}", config.dem_path, config.domain,
               instance_.instance_id, std::chrono::duration<double>(Clock::now() - started).count());
  return Status::success();
}

std::optional<ServiceInstance> MissionService::olderRival() {
  const std::string service_id = config().service_id;
  std::optional<ServiceInstance> older;
  for (const ServiceInstance& other : matchedInstances(edge_->rivals->handle())) {
    if (other.service_id != service_id || other.instance_id == instance_.instance_id) continue;
    if (!predecessor_instance_id_.empty() && other.instance_id == predecessor_instance_id_) continue;
    if (!other.rivals(instance_)) {  // a primary and its standby serve one service_id together
      if (std::find(partners_logged_.begin(), partners_logged_.end(), other.instance_id) == partners_logged_.end()) {
        partners_logged_.push_back(other.instance_id);
        spdlog::info("event=partner_instance service_id={} role={} partner=\"{}\"", service_id, instance_.role,
                     other.describe());
      }
      continue;
    }
    if (other.precedes(instance_)) {
      older = other;
    } else if (std::find(younger_rivals_logged_.begin(), younger_rivals_logged_.end(), other.instance_id) ==
               younger_rivals_logged_.end()) {
      younger_rivals_logged_.push_back(other.instance_id);
      spdlog::warn("event=rival_instance service_id={} rival=\"{}\" message=\"another daemon serves this service_id "
                   "on domain {}; it started later and will stop\"",
                   service_id, other.describe(), edge_->domain);
    }
  }
  return older;
}

void MissionService::checkRivals() {
  if (conflict_reported_) return;
  const std::optional<ServiceInstance> rival = olderRival();
  if (!rival) return;
  conflict_reported_ = true;
  const std::string message = "another skyrouted serves service_id '" + config().service_id + "' on domain " +
                              std::to_string(edge_->domain) + ": " + rival->describe() +
                              ", started before this one; stopping (give each daemon its own dds.service_id or domain)";
  spdlog::critical("event=service_conflict instance={} message=\"{}\"", instance_.instance_id, message);
  if (on_conflict_) on_conflict_(message);
}

Status MissionService::activate() {
  if (state_ != State::kInactive) {
    return make_error(ErrorCode::kInvalidArgument, "lifecycle", "activate needs the inactive state");
  }
  // Discovery on a domain takes a moment: before serving, listen for an older daemon with this
  // service_id. No sample is taken meanwhile, so a refused start answers nothing.
  // A probe of 0 s skips the check: the daemon serves at once and meets rivals through discovery.
  const auto probe_end = Clock::now() + seconds(config().startup_probe_s);
  while (config().startup_probe_s > 0.0) {
    if (const std::optional<ServiceInstance> rival = olderRival()) {
      return make_error(ErrorCode::kInvalidArgument, "dds.service_id",
                        "another skyrouted already serves service_id '" + config().service_id + "' on domain " +
                            std::to_string(edge_->domain) + ": " + rival->describe() +
                            "; not starting (give each daemon its own dds.service_id or domain)");
    }
    if (Clock::now() >= probe_end) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (recovered_) {
    if (router_) {
      // A shard takes its vehicles from the wire and its own copy of the requests (the group may
      // have moved them while it was down): from the journal the world, the plan counter and
      // its copies of the requests, which go to the router, not to the engine.
      recovered_->missions.clear();
      recovered_->trajectories.clear();
      recovered_->fleets.clear();
      recoverShardCopies(recovered_->shard_requests);
    }
    catchUpFromPartner(*recovered_);
    engine_->recover(*recovered_);
    recovered_.reset();
  }
  engine_->start();
  if (router_) {
    startShard();
    startStallWatch();
  }
  startDdsThread();
  state_ = State::kActive;
  spdlog::info("event=active service_id={} domain={} instance={}", config().service_id, edge_->domain,
               instance_.instance_id);
  return Status::success();
}

void MissionService::startDdsThread() {
  dds_thread_ = std::thread([this] { ddsThread(); });
}

void MissionService::stopDdsThread() {
  if (!dds_thread_.joinable()) return;
  edge_->loop->stop();
  dds_thread_.join();
  answerReachable(Clock::now(), /*all=*/true);  // nothing read is left unanswered
}

void MissionService::answerWhenReachable(const std::string& requester, std::function<void()> answer) {
  const bool queued_before = std::any_of(pending_answers_.begin(), pending_answers_.end(),
                                         [&](const PendingAnswer& p) { return p.requester == requester; });
  if (requester.empty() || (!queued_before && reachesParticipantOf(edge_->statuses->handle(), requester))) {
    answer();
    return;
  }
  pending_answers_.push_back({Clock::now() + seconds(kAnswerWaitS), requester, std::move(answer)});
}

void MissionService::answerReachable(Clock::time_point now, bool all) {
  std::set<std::string> waiting;  // requesters with an earlier answer still held: keep the order
  std::vector<PendingAnswer> held;
  std::vector<PendingAnswer> pending = std::move(pending_answers_);
  pending_answers_.clear();
  for (PendingAnswer& p : pending) {
    const bool due = all || now >= p.give_up_at ||
                     (!waiting.count(p.requester) && reachesParticipantOf(edge_->statuses->handle(), p.requester));
    if (!due) {
      waiting.insert(p.requester);
      held.push_back(std::move(p));
      continue;
    }
    if (now >= p.give_up_at && !all) {
      spdlog::warn("event=answer_unreached requester={} waited_s={:.1f} message=\"no status reader of the client "
                   "matched; answering anyway\"",
                   p.requester, kAnswerWaitS);
    }
    p.answer();
  }
  // Answers may queue more (a cancel's engine call does not, but keep them after the held ones).
  held.insert(held.end(), std::make_move_iterator(pending_answers_.begin()),
              std::make_move_iterator(pending_answers_.end()));
  pending_answers_ = std::move(held);
}

Status MissionService::deactivate() {
  if (state_ != State::kActive) return Status::success();
  // One deadline for the whole stop: the time the engine takes to stop its plans counts against
  // dds.flush_timeout_s too, so a stop is never the cancel's time plus the whole flush.
  const auto began = Clock::now();
  const auto deadline = began + seconds(config().flush_timeout_s);
  // The engine first: its plans see the cancel at their next check, and each is answered
  // cancelled while the writers are still there. Requests arriving meanwhile are refused busy.
  engine_->stop();
  stopDdsThread();
  const auto engine_stopped = Clock::now();
  if (stall_watch_) stall_watch_->stop();
  if (journal_) {
    const JournalWriteStats w = journal_->writeStats();
    spdlog::info("event=journal_stats writes={} mean_ms={:.3f} max_ms={:.3f}", w.writes,
                 w.writes ? w.total_ms / static_cast<double>(w.writes) : 0.0, w.max_ms);
  }
  // Flush: reliable readers get what was written, all writers sharing what is left of the deadline.
  auto left_s = [&] { return std::max(0.0, std::chrono::duration<double>(deadline - Clock::now()).count()); };
  {
    std::shared_lock lock(edge_mutex_);
    (void)edge_->statuses->waitForAcks(left_s());
    (void)edge_->fleet_statuses->waitForAcks(left_s());
    (void)edge_->trajectories->waitForAcks(left_s());
    if (edge_->ros2) edge_->ros2->flush(left_s());
  }
  state_ = State::kInactive;
  const auto flushed = Clock::now();
  spdlog::info("event=inactive engine_stop_s={:.3f} flush_s={:.3f}",
               std::chrono::duration<double>(engine_stopped - began).count(),
               std::chrono::duration<double>(flushed - engine_stopped).count());
  return Status::success();
}

Status MissionService::cleanup() {
  if (state_ == State::kActive) {
    return make_error(ErrorCode::kInvalidArgument, "lifecycle", "cleanup needs the inactive state");
  }
  if (state_ == State::kUnconfigured) return Status::success();
  stall_watch_.reset();
  engine_.reset();
  journal_sink_.reset();
  journal_.reset();
  recovered_.reset();
  state_lock_.reset();  // after the journal is closed
  {
    std::unique_lock lock(edge_mutex_);
    edge_.reset();
  }
  world_.reset();
  state_ = State::kUnconfigured;
  return Status::success();
}

Status MissionService::reload(const DaemonConfig& config) {
  if (state_ == State::kUnconfigured) {
    return make_error(ErrorCode::kInvalidArgument, "lifecycle", "reload needs a configured service");
  }
  const DaemonConfig old = this->config();
  // Everything is checked and built first; nothing running changes until all of it worked.
  if (Status ok = validateEngineOptions(config.engine); !ok.ok()) return ok;
  if (config.state_dir != old.state_dir) {
    return make_error(ErrorCode::kInvalidArgument, "service.state_dir",
                      "the state journal's folder cannot change while the daemon runs (restart it to use " +
                          (config.state_dir.empty() ? std::string("none") : config.state_dir) + ")");
  }
  if (config.shard_group != old.shard_group || (!old.shard_group.empty() && config.service_id != old.service_id)) {
    return make_error(ErrorCode::kInvalidArgument, config.shard_group != old.shard_group ? "service.shard_group" : "dds.service_id",
                      "a shard's group and service id cannot change while the daemon runs (restart it)");
  }
  std::shared_ptr<WorldModel> world;
  if (terrainChanged(old, config)) {
    if (Status free = engine_->canReplaceWorld(); !free.ok()) return free;  // before loading a large DEM
    auto loaded = loadWorld(config);
    if (!loaded.ok()) return loaded.error();
    world = std::move(*loaded);
  }
  std::unique_ptr<Edge> edge;
  const bool edge_changed = edgeChanged(old, config);
  if (edge_changed) {
    auto made = makeEdge(config, world ? *world : *world_);
    if (!made.ok()) return made.error();
    edge = std::move(*made);
  }
  // The only step that can still fail: a mission may have arrived since the check above.
  if (world) {
    if (Status ok = engine_->replaceWorld(world); !ok.ok()) return ok;
    world_ = world;
  }
  if (edge_changed) {
    const bool active = state_ == State::kActive;
    if (active) stopDdsThread();
    {
      std::unique_lock lock(edge_mutex_);
      std::swap(edge_, edge);
    }
    instance_.service_id = config.service_id;
    instance_.role = config.role;
    younger_rivals_logged_.clear();
    partners_logged_.clear();
    alive_heartbeat_writers_ = 0;  // counted anew by the new heartbeat reader
    republish_at_.clear();
    conflict_reported_ = false;
    if (active) startDdsThread();
  }
  (void)engine_->setOptions(config.engine);  // validated above
  bad_samples_log_.setWindowS(config.engine.log_repeat_window_s);
  fence_log_.setWindowS(config.engine.log_repeat_window_s);
  if (stall_watch_) stall_watch_->setThresholdS(config.liveliness_lease_s * kStallFractionOfLease);
  {
    std::lock_guard lock(config_mutex_);
    config_ = config;
  }
  // On a new domain, ground stations there get every active mission's current trajectory
  // (transient-local) as they would have on the old one.
  std::size_t republished = 0;
  if (edge_changed) {
    for (const TrajectoryData& t : engine_->currentTrajectories()) {
      publishTrajectory(t);
      ++republished;
    }
  }
  spdlog::info("event=reloaded terrain_changed={} domain_changed={} planning_threads={} missions={} obstacles={} "
               "republished={}",
               world != nullptr, edge_changed, config.engine.planning_threads, engine_->activeMissions(),
               engine_->world()->obstacleCount(), republished);
  return Status::success();
}

void MissionService::publishStatus(const PlanStatusData& status) {
  std::shared_lock ownership(ownership_mutex_);
  if (router_ && !router_->ownsVehicle(status.vehicle_id)) return;  // its owner answers
  if (router_ && fencedByStall("status", status.vehicle_id)) return;
  PlanStatusData addressed = status;
  addressed.service_instance = instance_.instance_id;
  addressed.service_id = instance_.service_id;
  std::shared_lock lock(edge_mutex_);
  if (Status s = edge_->statuses->write(addressed); !s.ok()) {
    spdlog::error("event=write_failed topic=status field={} message=\"{}\"", s.error().field, s.error().message);
  }
}

void MissionService::publishTrajectory(const TrajectoryData& trajectory) {
  std::shared_lock ownership(ownership_mutex_);
  if (router_) {
    if (!router_->ownsVehicle(trajectory.vehicle_id)) return;
    if (fencedByStall("trajectory", trajectory.vehicle_id)) return;
    // One (plan id, revision) never stands for two trajectories: what another daemon already
    // published of this plan at this revision or later is not overwritten from here.
    if (router_->supersededOnWire(trajectory)) {
      fence_log_.warn("superseded:" + trajectory.vehicle_id,
                      fmt::format("event=publication_fenced topic=trajectory vehicle={} plan={} revision={} "
                                  "reason=superseded message=\"another daemon published this revision of the plan "
                                  "or a later one\"",
                                  trajectory.vehicle_id, trajectory.plan_id, trajectory.revision));
      return;
    }
  }
  std::shared_lock lock(edge_mutex_);
  if (Status s = edge_->trajectories->write(trajectory); !s.ok()) {
    spdlog::error("event=write_failed topic=trajectory field={} message=\"{}\"", s.error().field, s.error().message);
  } else if (router_) {
    router_->onPublished(trajectory);
  }
  if (edge_->ros2) edge_->ros2->publish(trajectory);
}

void MissionService::retractTrajectory(const std::string& vehicle_id) {
  std::shared_lock ownership(ownership_mutex_);
  if (router_ && !router_->ownsVehicle(vehicle_id)) return;
  if (router_ && fencedByStall("retraction", vehicle_id)) return;
  TrajectoryData key;
  key.vehicle_id = vehicle_id;
  std::shared_lock lock(edge_mutex_);
  if (Status s = edge_->trajectories->dispose(key); !s.ok()) {
    spdlog::error("event=dispose_failed vehicle={} message=\"{}\"", vehicle_id, s.error().message);
  }
  if (edge_->ros2) edge_->ros2->retract(vehicle_id);
}

void MissionService::publishFleetStatus(const FleetStatusData& status) {
  std::shared_lock ownership(ownership_mutex_);
  if (router_ && !router_->ownsFleet(status.request_id)) return;
  if (router_ && fencedByStall("fleet_status", status.request_id)) return;
  std::shared_lock lock(edge_mutex_);
  if (Status s = edge_->fleet_statuses->write(status); !s.ok()) {
    spdlog::error("event=write_failed topic=fleet_status field={} message=\"{}\"", s.error().field, s.error().message);
  }
}

void MissionService::publishHeartbeat() {
  const DaemonConfig config = this->config();
  ServiceStatusData status = engine_->status(config.service_id);
  status.instance_id = instance_.instance_id;
  status.started_utc_ns = instance_.started_utc_ns;
  status.heartbeat_period_s = config.heartbeat_period_s;
  status.service_version = SKYROUTE_VERSION;
  status.idl_version = kIdlVersion;
  status.journal_ok = !journal_ || journal_->writable();
  status.life_started_utc_ns = life_started_utc_ns_;
  std::shared_lock lock(edge_mutex_);
  (void)edge_->heartbeat->write(status);
}

void MissionService::checkPartnerLoss() {
  dds_liveliness_changed_status_t status{};
  if (dds_get_liveliness_changed_status(edge_->rivals->handle(), &status) != DDS_RETCODE_OK) return;
  const std::uint32_t alive = status.alive_count;
  const bool lost = alive < alive_heartbeat_writers_;
  alive_heartbeat_writers_ = alive;
  if (!lost || config().role != "standby") return;
  follow_wire_revisions_ = true;
  // A heartbeat writer died or left: perhaps the primary. Its readers now take this standby's
  // samples, but only those written after they noticed, and the revisions this standby wrote
  // meanwhile were refused: publish every current trajectory again. Readers notice the lost lease
  // at about the same moment as this daemon, not exactly then: twice, a little apart.
  const auto now = Clock::now();
  const double lease_s = config().liveliness_lease_s;
  republish_at_.push_back(now + seconds(std::min(0.1, lease_s / 2)));
  republish_at_.push_back(now + seconds(std::min(0.4, lease_s)));
  std::sort(republish_at_.begin(), republish_at_.end());
  spdlog::info("event=partner_lost role=standby alive_heartbeat_writers={} message=\"republishing every current "
               "trajectory for the readers this standby now serves\"",
               alive);
}

void MissionService::noteWireRevision(const TrajectoryData& trajectory) {
  // The reader is exclusive too: while the primary lives, its samples; this daemon's own once it
  // owns the instance, which say nothing about the primary's numbering.
  if (trajectory.source_instance == instance_.instance_id) return;
  wire_revisions_[trajectory.vehicle_id] = WireRevision{trajectory.plan_id, trajectory.revision};
}

void MissionService::followWireRevisions() {
  for (const auto& [vehicle, wire] : wire_revisions_) {
    if (engine_->followRevision(vehicle, wire.plan_id, wire.revision)) renumbered_.insert(vehicle);
  }
  spdlog::info("event=takeover_revisions vehicles_on_wire={} renumbered={}", wire_revisions_.size(), renumbered_.size());
  // Numbered from the primary's last revision once: a later takeover (of a restarted primary)
  // follows what that one publishes meanwhile.
  wire_revisions_.clear();
}

void MissionService::republishDue(Clock::time_point now) {
  if (republish_at_.empty() || now < republish_at_.front()) return;
  republish_at_.erase(republish_at_.begin());
  if (follow_wire_revisions_) {
    follow_wire_revisions_ = false;
    followWireRevisions();
  }
  std::size_t n = 0;
  for (const TrajectoryData& t : engine_->currentTrajectories()) {
    if (router_ && !taken_vehicles_.contains(t.vehicle_id)) continue;  // only those that just moved here
    if (journal_sink_ && renumbered_.erase(t.vehicle_id) > 0) {
      // A new revision number: into the journal first; one it cannot record is not published.
      if (!journal_sink_->recordTrajectory(t).ok()) continue;
    }
    publishTrajectory(t);
    ++n;
  }
  if (republish_at_.empty()) taken_vehicles_.clear();
  spdlog::info("event=takeover_republished trajectories={}", n);
}

void MissionService::catchUpFromPartner(JournalState& state) {
  if (config().role != "primary" || state.trajectories.empty()) return;
  // A primary restarting on its journal while its standby served: the standby may have
  // published newer revisions of the same plans (replans during the outage), or a new plan for a
  // vehicle. Ground stations take the primary's samples as soon as it writes, so it must not
  // write what is older than what they have. Its trajectory reader is a late joiner of the
  // standby's transient-local history (its own writer has written nothing yet).
  // The startup probe has listened for the daemons on the domain by now.
  bool partner = false;
  for (const ServiceInstance& other : matchedInstances(edge_->rivals->handle())) {
    if (other.service_id == instance_.service_id && other.role == "standby") partner = true;
  }
  if (!partner) return;
  auto reader = Reader<TrajectoryData>::create(edge_->participant.get());
  if (!reader.ok()) {
    spdlog::warn("event=catch_up_failed message=\"{}\"", reader.error().describe());
    return;
  }
  // Its own trajectory writer matches too: at least two writers.
  (void)reader->waitForWriters(2, 2.0);
  std::map<std::string, TrajectoryData> on_bus;
  const auto read_end = Clock::now() + seconds(0.5);
  while (Clock::now() < read_end) {
    (void)reader->takeAvailable(
        [&](TrajectoryData&& t) {
          const std::string vehicle = t.vehicle_id;
          on_bus[vehicle] = std::move(t);
        },
        [](const Error&) {});
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::size_t adopted = 0, handed_over = 0;
  std::vector<std::string> dropped;
  for (TrajectoryData& t : state.trajectories) {
    auto bus = on_bus.find(t.vehicle_id);
    if (bus == on_bus.end()) continue;
    if (bus->second.plan_id == t.plan_id) {
      if (bus->second.revision > t.revision) {
        t = bus->second;
        t.source_instance.clear();
        t.source_role.clear();
        ++adopted;
      }
    } else if (bus->second.created_utc_ns > t.created_utc_ns) {
      dropped.push_back(t.vehicle_id);  // a newer plan the standby made alone: it keeps serving it
    }
  }
  for (const std::string& vehicle : dropped) {
    std::erase_if(state.trajectories, [&](const TrajectoryData& t) { return t.vehicle_id == vehicle; });
    std::erase_if(state.missions, [&](const JournalState::Mission& m) { return m.request.vehicle_id == vehicle; });
    ++handed_over;
  }
  spdlog::info("event=caught_up trajectories_on_bus={} adopted={} left_to_standby={}", on_bus.size(), adopted,
               handed_over);
}

void MissionService::ddsThread() {
  // The edge is swapped only while this thread is stopped, so it is read here without the lock.
  WaitLoop& loop = *edge_->loop;
  auto next_heartbeat = Clock::now();
  for (;;) {
    // First: a shard that stood still for longer than its stall threshold publishes nothing more
    // (not even a heartbeat of the life it had) before it has begun a new one.
    if (stall_watch_ && stall_watch_->suspect()) beginShardLife("stall");
    const auto now = Clock::now();
    republishDue(now);
    shardCheckDue(now);
    if (!pending_answers_.empty()) answerReachable(now, /*all=*/false);
    if (now >= next_heartbeat) {
      publishHeartbeat();
      scheduleShardCheck();  // a restarted member's first heartbeat makes it live again
      recordShardCoverage();
      // On the period's grid, so a late heartbeat does not delay every later one.
      const auto period = seconds(config().heartbeat_period_s);
      next_heartbeat = now - next_heartbeat < period ? next_heartbeat + period : now + period;
      bad_samples_log_.flush(now);
    }
    auto wake = republish_at_.empty() ? next_heartbeat : std::min(next_heartbeat, republish_at_.front());
    if (!shard_check_at_.empty()) wake = std::min(wake, shard_check_at_.front());
    constexpr auto kReachCheckPeriod = std::chrono::milliseconds(20);
    if (!pending_answers_.empty()) wake = std::min(wake, Clock::now() + kReachCheckPeriod);
    const double wait_s = std::chrono::duration<double>(wake - Clock::now()).count();
    auto outcome = loop.runOnce(std::max(wait_s, 0.0));
    if (!outcome.ok()) {
      // A DDS failure on one take must not end the service: log it and go on.
      spdlog::error("event=waitset_error field={} message=\"{}\"", outcome.error().field, outcome.error().message);
      continue;
    }
    if (*outcome == WaitLoop::Outcome::kStopped) return;
  }
}

}  // namespace skyroute::dds
