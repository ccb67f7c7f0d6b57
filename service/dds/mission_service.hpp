// skyrouted's node: the engine behind its DDS edge, with an explicit lifecycle as Nav2's managed
// nodes (configure -> activate -> deactivate -> cleanup). Requests, cancels and obstacle updates
// are taken on the node's own thread through a waitset (never in Cyclone's listener threads) and
// only queued there; planning runs on the engine's threads. Trajectories go out reliable,
// transient-local, keep-last 1 per vehicle, so a ground station that joins late gets every
// vehicle's current trajectory; statuses reliable; a ServiceStatus heartbeat every period.
#pragma once

#include <atomic>
#include <memory>
#include <optional>
#include <thread>

#include "service/daemon_config.hpp"
#include "service/dds/ros2_mirror.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/engine.hpp"

namespace skyroute::dds {

class MissionService final : public EngineSink {
 public:
  enum class State { kUnconfigured, kInactive, kActive };

  MissionService() = default;
  ~MissionService() override;
  MissionService(const MissionService&) = delete;
  MissionService& operator=(const MissionService&) = delete;

  // Loads the terrain, makes the world model and the engine, creates the DDS entities.
  // config.dem_path must be set. Errors name the key or the file.
  Status configure(const DaemonConfig& config);
  // Starts the engine's threads and the node's DDS thread.
  Status activate();
  // Stops taking samples (the waitset's guard is triggered), cancels in-flight plans, ends the
  // threads and waits up to flush_timeout_s for readers to acknowledge what was written.
  Status deactivate();
  // Releases the engine, the world and every DDS entity.
  Status cleanup();
  // A new configuration (SIGHUP): tunables apply to the requests that follow; a new terrain or
  // DDS domain restarts the node (deactivate, cleanup, configure, activate).
  Status reload(const DaemonConfig& config);

  State state() const { return state_; }
  const DaemonConfig& config() const { return config_; }
  // The waitset's handle, for a signal handler that only triggers it (WaitLoop::signalStop).
  dds_entity_t waitsetHandle() const { return loop_ ? loop_->waitsetHandle() : 0; }

  // EngineSink: called from the engine's threads.
  void publishStatus(const PlanStatusData& status) override;
  void publishTrajectory(const TrajectoryData& trajectory) override;
  void retractTrajectory(const std::string& vehicle_id) override;
  void publishFleetStatus(const FleetStatusData& status) override;

 private:
  void ddsThread();
  void publishHeartbeat();

  DaemonConfig config_;
  State state_ = State::kUnconfigured;
  std::shared_ptr<WorldModel> world_;
  std::unique_ptr<Engine> engine_;
  // DDS entities: the participant first, so it is destroyed last.
  Entity participant_;
  std::optional<Reader<MissionRequestData>> requests_;
  std::optional<Reader<CancelRequestData>> cancels_;
  std::optional<Reader<ObstacleUpdateData>> obstacles_;
  std::optional<Writer<TrajectoryData>> trajectories_;
  std::optional<Writer<PlanStatusData>> statuses_;
  std::optional<Writer<ServiceStatusData>> heartbeat_;
  // Fleets (issue 7): FleetRequest in, FleetStatus out (trajectories on the same writer).
  std::optional<Reader<FleetRequestData>> fleet_requests_;
  std::optional<Writer<FleetStatusData>> fleet_statuses_;
  std::unique_ptr<Ros2Mirror> ros2_;  // ROS 2 topics of every trajectory (ros2.enabled)
  std::optional<WaitLoop> loop_;
  std::thread dds_thread_;
  std::atomic<std::uint64_t> bad_samples_{0};
};

}  // namespace skyroute::dds
