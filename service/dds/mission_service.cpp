#include "service/dds/mission_service.hpp"

#include <chrono>
#include <filesystem>

#include <spdlog/spdlog.h>


namespace skyroute::dds {
namespace {

// The IDL revision of idl/skyroute.idl: bump when a message changes incompatibly.
constexpr const char* kIdlVersion = "skyroute_msgs/1";

}  // namespace

MissionService::~MissionService() {
  (void)deactivate();
  (void)cleanup();
}

Status MissionService::configure(const DaemonConfig& config) {
  if (state_ != State::kUnconfigured) {
    return make_error(ErrorCode::kInvalidArgument, "lifecycle", "configure needs the unconfigured state");
  }
  if (config.dem_path.empty()) return make_error(ErrorCode::kInvalidArgument, "terrain.dem", "no DEM path");
  const auto started = std::chrono::steady_clock::now();
  auto world = WorldModel::load(config.dem_path, config.world);
  if (!world.ok()) {
    Error e = world.error();
    e.message = "terrain.dem " + config.dem_path + ": " + e.message;
    return e;
  }
  auto engine = Engine::create(*world, config.engine, *this);
  if (!engine.ok()) return engine.error();

  auto participant = createParticipant(static_cast<dds_domainid_t>(config.domain));
  if (!participant.ok()) return participant.error();
  const dds_entity_t p = participant->get();
  auto requests = Reader<MissionRequestData>::create(p);
  if (!requests.ok()) return requests.error();
  auto cancels = Reader<CancelRequestData>::create(p);
  if (!cancels.ok()) return cancels.error();
  auto obstacles = Reader<ObstacleUpdateData>::create(p);
  if (!obstacles.ok()) return obstacles.error();
  auto trajectories = Writer<TrajectoryData>::create(p);
  if (!trajectories.ok()) return trajectories.error();
  auto statuses = Writer<PlanStatusData>::create(p);
  if (!statuses.ok()) return statuses.error();
  auto heartbeat = Writer<ServiceStatusData>::create(p);
  if (!heartbeat.ok()) return heartbeat.error();
  auto fleet_requests = Reader<FleetRequestData>::create(p);
  if (!fleet_requests.ok()) return fleet_requests.error();
  auto fleet_statuses = Writer<FleetStatusData>::create(p);
  if (!fleet_statuses.ok()) return fleet_statuses.error();
  auto loop = WaitLoop::create(p);
  if (!loop.ok()) return loop.error();
  std::unique_ptr<Ros2Mirror> ros2 = config.ros2_enabled ? Ros2Mirror::create(p, (*world)->frame().anchor()) : nullptr;

  config_ = config;
  world_ = std::move(*world);
  engine_ = std::move(*engine);
  participant_ = std::move(*participant);
  requests_.emplace(std::move(*requests));
  cancels_.emplace(std::move(*cancels));
  obstacles_.emplace(std::move(*obstacles));
  trajectories_.emplace(std::move(*trajectories));
  statuses_.emplace(std::move(*statuses));
  heartbeat_.emplace(std::move(*heartbeat));
  fleet_requests_.emplace(std::move(*fleet_requests));
  fleet_statuses_.emplace(std::move(*fleet_statuses));
  loop_.emplace(std::move(*loop));
  ros2_ = std::move(ros2);

  // Handlers only queue or flag: planning happens on the engine's threads.
  Status added = loop_->addWithRejects(
      *requests_, [this](MissionRequestData&& request) { engine_->submit(std::move(request)); },
      [this](const Error& e, const MissionRequestData& identity) {
        ++bad_samples_;
        spdlog::warn("event=bad_request request={} vehicle={} field={} message=\"{}\"", identity.request_id,
                     identity.vehicle_id, e.field, e.message);
        publishStatus(PlanStatusData::failed(identity, toPlanError(e), 0.0));
      });
  if (!added.ok()) return added;
  added = loop_->add(
      *cancels_, [this](CancelRequestData&& cancel) { engine_->cancel(cancel); },
      [this](const Error& e) {
        ++bad_samples_;
        spdlog::warn("event=bad_cancel field={} message=\"{}\"", e.field, e.message);
      });
  if (!added.ok()) return added;
  added = loop_->add(
      *obstacles_, [this](ObstacleUpdateData&& update) { engine_->updateObstacle(update); },
      [this](const Error& e) {
        ++bad_samples_;
        spdlog::warn("event=bad_obstacle_update field={} message=\"{}\"", e.field, e.message);
      });
  if (!added.ok()) return added;

  added = loop_->addWithRejects(
      *fleet_requests_, [this](FleetRequestData&& request) { engine_->submitFleet(std::move(request)); },
      [this](const Error& e, const FleetRequestData& identity) {
        ++bad_samples_;
        spdlog::warn("event=bad_fleet_request request={} field={} message=\"{}\"", identity.request_id, e.field,
                     e.message);
        const PlanError error = toPlanError(e);
        FleetStatusData status;
        status.request_id = identity.request_id;
        status.state = PlanState::kFailed;
        status.error_code = error.code;
        status.field = error.field;
        status.message = error.describe();
        publishFleetStatus(status);
      });
  if (!added.ok()) return added;

  state_ = State::kInactive;
  spdlog::info("event=configured dem={} domain={} time_s={:.2f}", config.dem_path, config.domain,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  return Status::success();
}

Status MissionService::activate() {
  if (state_ != State::kInactive) {
    return make_error(ErrorCode::kInvalidArgument, "lifecycle", "activate needs the inactive state");
  }
  engine_->start();
  dds_thread_ = std::thread([this] { ddsThread(); });
  state_ = State::kActive;
  spdlog::info("event=active service_id={} domain={}", config_.service_id, config_.domain);
  return Status::success();
}

Status MissionService::deactivate() {
  if (state_ != State::kActive) return Status::success();
  loop_->stop();
  if (dds_thread_.joinable()) dds_thread_.join();
  engine_->stop();  // cancels in-flight plans; their cancelled statuses still go out
  // Flush: reliable readers get what was written before the writers go away.
  const double flush_s = config_.flush_timeout_s;
  (void)statuses_->waitForAcks(flush_s);
  (void)fleet_statuses_->waitForAcks(flush_s);
  (void)trajectories_->waitForAcks(flush_s);
  if (ros2_) ros2_->flush(flush_s);
  state_ = State::kInactive;
  spdlog::info("event=inactive");
  return Status::success();
}

Status MissionService::cleanup() {
  if (state_ == State::kActive) {
    return make_error(ErrorCode::kInvalidArgument, "lifecycle", "cleanup needs the inactive state");
  }
  if (state_ == State::kUnconfigured) return Status::success();
  engine_.reset();
  loop_.reset();
  ros2_.reset();
  heartbeat_.reset();
  fleet_statuses_.reset();
  fleet_requests_.reset();
  statuses_.reset();
  trajectories_.reset();
  obstacles_.reset();
  cancels_.reset();
  requests_.reset();
  participant_ = Entity();
  world_.reset();
  state_ = State::kUnconfigured;
  return Status::success();
}

Status MissionService::reload(const DaemonConfig& config) {
  const bool restart = config.dem_path != config_.dem_path || config.domain != config_.domain ||
                       config.world.vehicle_radius_m != config_.world.vehicle_radius_m ||
                       config.world.terrain_margin_m != config_.world.terrain_margin_m ||
                       config.engine.planning_threads != config_.engine.planning_threads ||
                       config.ros2_enabled != config_.ros2_enabled;
  if (!restart) {
    engine_->setOptions(config.engine);
    config_ = config;
    spdlog::info("event=reloaded restart=false");
    return Status::success();
  }
  const bool was_active = state_ == State::kActive;
  if (Status s = deactivate(); !s.ok()) return s;
  if (Status s = cleanup(); !s.ok()) return s;
  if (Status s = configure(config); !s.ok()) return s;
  if (was_active) {
    if (Status s = activate(); !s.ok()) return s;
  }
  spdlog::info("event=reloaded restart=true");
  return Status::success();
}

void MissionService::publishStatus(const PlanStatusData& status) {
  if (Status s = statuses_->write(status); !s.ok()) {
    spdlog::error("event=write_failed topic=status field={} message=\"{}\"", s.error().field, s.error().message);
  }
}

void MissionService::publishTrajectory(const TrajectoryData& trajectory) {
  if (Status s = trajectories_->write(trajectory); !s.ok()) {
    spdlog::error("event=write_failed topic=trajectory field={} message=\"{}\"", s.error().field, s.error().message);
  }
  if (ros2_) ros2_->publish(trajectory);
}

void MissionService::retractTrajectory(const std::string& vehicle_id) {
  TrajectoryData key;
  key.vehicle_id = vehicle_id;
  if (Status s = trajectories_->dispose(key); !s.ok()) {
    spdlog::error("event=dispose_failed vehicle={} message=\"{}\"", vehicle_id, s.error().message);
  }
  if (ros2_) ros2_->retract(vehicle_id);
}

void MissionService::publishFleetStatus(const FleetStatusData& status) {
  if (Status s = fleet_statuses_->write(status); !s.ok()) {
    spdlog::error("event=write_failed topic=fleet_status field={} message=\"{}\"", s.error().field, s.error().message);
  }
}

void MissionService::publishHeartbeat() {
  ServiceStatusData status = engine_->status(config_.service_id);
  status.service_version = SKYROUTE_VERSION;
  status.idl_version = kIdlVersion;
  (void)heartbeat_->write(status);
}

void MissionService::ddsThread() {
  using Clock = std::chrono::steady_clock;
  auto next_heartbeat = Clock::now();
  for (;;) {
    const auto now = Clock::now();
    if (now >= next_heartbeat) {
      publishHeartbeat();
      next_heartbeat = now + std::chrono::duration_cast<Clock::duration>(
                                 std::chrono::duration<double>(config_.heartbeat_period_s));
    }
    const double wait_s = std::chrono::duration<double>(next_heartbeat - Clock::now()).count();
    auto outcome = loop_->runOnce(std::max(wait_s, 0.0));
    if (!outcome.ok()) {
      // A DDS failure on one take must not end the service: log it and go on.
      spdlog::error("event=waitset_error field={} message=\"{}\"", outcome.error().field, outcome.error().message);
      continue;
    }
    if (*outcome == WaitLoop::Outcome::kStopped) return;
  }
}

}  // namespace skyroute::dds
