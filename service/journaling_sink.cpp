#include "service/journaling_sink.hpp"

#include <spdlog/spdlog.h>

namespace skyroute {

namespace {

const Status& logFailed(const char* event, const Status& s) {
  if (!s.ok()) spdlog::error("event=journal_write_failed what={} message=\"{}\"", event, s.error().message);
  return s;
}

}  // namespace

JournalingSink::JournalingSink(EngineSink& next, std::shared_ptr<StateJournal> journal, Engine::Clock clock)
    : next_(next), journal_(std::move(journal)), clock_(std::move(clock)) {}

void JournalingSink::publishStatus(const PlanStatusData& status) {
  // A duplicate's refusal is about the new sample only: the request it repeats goes on.
  const bool ends_request = (status.state == PlanState::kFailed || status.state == PlanState::kCancelled) &&
                            status.error_code != PlanErrorCode::kDuplicateRequest && !status.vehicle_id.empty();
  if (ends_request) logFailed("finished", journal_->recordFinished(status.vehicle_id, status.request_id));
  next_.publishStatus(status);
}

// Recorded by the engine first (recordTrajectory, recordFleetPlan), or read from the journal.
void JournalingSink::publishTrajectory(const TrajectoryData& trajectory) { next_.publishTrajectory(trajectory); }

void JournalingSink::retractTrajectory(const std::string& vehicle_id) {
  logFailed("retracted", journal_->recordRetracted(vehicle_id));
  next_.retractTrajectory(vehicle_id);
}

// A fleet's allocation is recorded with its trajectories (recordFleetPlan).
void JournalingSink::publishFleetStatus(const FleetStatusData& status) { next_.publishFleetStatus(status); }

Status JournalingSink::recordAccepted(const MissionRequestData& request) {
  return logFailed("accepted", journal_->recordAccepted(request, clock_()));
}

Status JournalingSink::recordTrajectory(const TrajectoryData& trajectory) {
  return logFailed("trajectory", journal_->recordTrajectory(trajectory, clock_()));
}

Status JournalingSink::recordFleetPlan(const std::vector<TrajectoryData>& trajectories, const FleetStatusData& status) {
  return logFailed("fleet", journal_->recordFleetPlan(trajectories, status, clock_()));
}

Status JournalingSink::recordCancel(const CancelRequestData& cancel) {
  return logFailed("cancel", journal_->recordCancel(cancel.vehicle_id, cancel.request_id));
}

void JournalingSink::recordObstacle(const ObstacleUpdateData& update) {
  logFailed("obstacle", journal_->recordObstacle(update));
}

void JournalingSink::recordNoFlyZone(const NoFlyZoneData& zone) { logFailed("nofly_zone", journal_->recordNoFlyZone(zone)); }

}  // namespace skyroute
