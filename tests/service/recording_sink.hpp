// An EngineSink that keeps what the engine published, in order, for the engine tests to read.
// The engine publishes from its planning and replanning threads, hence the lock.
#pragma once

#include <mutex>
#include <string>
#include <vector>

#include "service/engine.hpp"

namespace skyroute::testing {

class RecordingSink : public EngineSink {
 public:
  void publishStatus(const PlanStatusData& status) override {
    std::lock_guard lock(mutex_);
    statuses.push_back(status);
  }
  void publishTrajectory(const TrajectoryData& trajectory) override {
    std::lock_guard lock(mutex_);
    trajectories.push_back(trajectory);
  }
  void retractTrajectory(const std::string& vehicle_id) override {
    std::lock_guard lock(mutex_);
    retracted.push_back(vehicle_id);
  }
  void publishFleetStatus(const FleetStatusData& status) override {
    std::lock_guard lock(mutex_);
    fleet.push_back(status);
  }
  std::vector<PlanStatusData> statuses;
  std::vector<TrajectoryData> trajectories;
  std::vector<std::string> retracted;  // vehicle ids
  std::vector<FleetStatusData> fleet;

 private:
  std::mutex mutex_;
};

}  // namespace skyroute::testing
