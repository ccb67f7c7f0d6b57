#include "service/journal_screening.hpp"

#include <algorithm>
#include <string>

#include "service/no_fly_zone_data.hpp"
#include "service/obstacle_bounds.hpp"

namespace skyroute {

namespace {

std::string reasonOf(const PlanError& e) {
  return "refused today: " + std::string(to_string(e.code)) + (e.field.empty() ? "" : " " + e.field) + ": " + e.message;
}

}  // namespace

std::vector<QuarantinedRecord> screenJournalState(JournalState& state, const EngineOptions& options,
                                                  const WorldModel& world) {
  std::vector<QuarantinedRecord> refused;
  std::erase_if(state.missions, [&](const JournalState::Mission& m) {
    const std::optional<PlanError> problem = checkMissionAdmission(m.request, world, options);
    if (problem) refused.push_back({"missions", {m.request.vehicle_id, m.request.request_id}, reasonOf(*problem)});
    return problem.has_value();
  });
  std::erase_if(state.shard_requests, [&](const JournaledRequest& copy) {
    const std::optional<PlanError> problem = copy.fleet ? checkFleetAdmission(*copy.fleet, options)
                                                         : checkMissionAdmission(*copy.mission, world, options);
    if (problem) refused.push_back({"shard_requests", {copy.key}, reasonOf(*problem)});
    return problem.has_value();
  });
  std::erase_if(state.obstacles, [&](const ObstacleUpdateData& update) {
    std::optional<PlanError> problem = validateObstacleUpdate(update);
    if (!problem) problem = checkObstacleBounds(update, world.terrain(), options.obstacles);
    if (problem) refused.push_back({"obstacles", {std::to_string(update.obstacle.id)}, reasonOf(*problem)});
    return problem.has_value();
  });
  std::erase_if(state.zones, [&](const NoFlyZoneData& zone) {
    auto checked = toNoFlyZone(zone, world.frame());
    if (!checked.ok()) refused.push_back({"no_fly_zones", {zone.zone_id}, reasonOf(toPlanError(checked.error()))});
    return !checked.ok();
  });
  quarantineDependents(state, refused);
  return refused;
}

}  // namespace skyroute
