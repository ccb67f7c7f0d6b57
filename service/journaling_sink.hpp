// An EngineSink in front of another that writes each event to the state journal before passing
// it on (write-ahead): a trajectory or revision is recorded before it is published, an accepted
// request before its acceptance, a failed or cancelled request's end, a retraction, a fleet's
// allocation, obstacle updates and no-fly zones. A failed write is logged (an accepted request
// whose record fails is refused by the engine); publishing goes on.
#pragma once

#include <memory>

#include "service/engine.hpp"
#include "service/state_journal.hpp"

namespace skyroute {

class JournalingSink final : public EngineSink {
 public:
  JournalingSink(EngineSink& next, std::shared_ptr<StateJournal> journal, Engine::Clock clock = utcNowNs);

  void publishStatus(const PlanStatusData& status) override;
  void publishTrajectory(const TrajectoryData& trajectory) override;
  void retractTrajectory(const std::string& vehicle_id) override;
  void publishFleetStatus(const FleetStatusData& status) override;
  Status recordAccepted(const MissionRequestData& request) override;
  void recordObstacle(const ObstacleUpdateData& update) override;
  void recordNoFlyZone(const NoFlyZoneData& zone) override;

  StateJournal& journal() { return *journal_; }

 private:
  EngineSink& next_;
  std::shared_ptr<StateJournal> journal_;
  Engine::Clock clock_;
};

}  // namespace skyroute
