// An EngineSink in front of another that writes each event to the state journal before it is
// published or takes effect (write-ahead). The engine calls the record hooks first and publishes
// only what they recorded: an accepted request before its acceptance, a trajectory or revision
// (a fleet's with its allocation, in one transaction) before it goes out, a cancel before it takes
// effect; a hook that fails makes the engine refuse the work (journal_unavailable) or keep the
// revision in force. A failed or cancelled request's end, a retraction, obstacle updates and
// no-fly zones are recorded on their way; a failure there is logged (event=journal_write_failed)
// and the event goes on (docs/journal.md "A full disk" says why).
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
  Status recordTrajectory(const TrajectoryData& trajectory) override;
  Status recordFleetPlan(const std::vector<TrajectoryData>& trajectories, const FleetStatusData& status) override;
  Status recordCancel(const CancelRequestData& cancel) override;
  bool recordsTrajectories() const override { return true; }
  void recordObstacle(const ObstacleUpdateData& update) override;
  void recordNoFlyZone(const NoFlyZoneData& zone) override;

  StateJournal& journal() { return *journal_; }

 private:
  EngineSink& next_;
  std::shared_ptr<StateJournal> journal_;
  Engine::Clock clock_;
};

}  // namespace skyroute
