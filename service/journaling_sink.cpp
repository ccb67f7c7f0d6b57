#include "service/journaling_sink.hpp"

#include <spdlog/spdlog.h>

namespace skyroute {

namespace {

void logFailed(const char* event, const Status& s) {
  if (!s.ok()) spdlog::error("event=journal_write_failed what={} message=\"{}\"", event, s.error().message);
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

void JournalingSink::publishTrajectory(const TrajectoryData& trajectory) {
  logFailed("trajectory", journal_->recordTrajectory(trajectory, clock_()));
  next_.publishTrajectory(trajectory);
}

void JournalingSink::retractTrajectory(const std::string& vehicle_id) {
  logFailed("retracted", journal_->recordRetracted(vehicle_id));
  next_.retractTrajectory(vehicle_id);
}

void JournalingSink::publishFleetStatus(const FleetStatusData& status) {
  // A replanned fleet's allocation replaces the first one: a restart republishes what is in force.
  if (status.state == PlanState::kSucceeded || status.state == PlanState::kReplanned) {
    logFailed("fleet", journal_->recordFleet(status));
  }
  next_.publishFleetStatus(status);
}

Status JournalingSink::recordAccepted(const MissionRequestData& request) {
  return journal_->recordAccepted(request, clock_());
}

void JournalingSink::recordObstacle(const ObstacleUpdateData& update) {
  logFailed("obstacle", journal_->recordObstacle(update));
}

void JournalingSink::recordNoFlyZone(const NoFlyZoneData& zone) { logFailed("nofly_zone", journal_->recordNoFlyZone(zone)); }

}  // namespace skyroute
