// What the DDS tools share: opening a participant (or failing with a message and exit code),
// stopping a waitset on SIGINT/SIGTERM, and one-line descriptions of what arrives.
#pragma once

#include <string>

#include "planning/core/result.hpp"
#include "service/cli/cli_common.hpp"
#include "service/dds/dds_entities.hpp"
#include "service/mission_types.hpp"

namespace skyroute::cli {

dds::Entity openParticipant(const std::string& tool, int domain);

// SIGINT and SIGTERM trigger this waitset (only that, as the Cyclone examples do).
void stopOnSignals(dds_entity_t waitset);

std::string describe(const TrajectoryData& trajectory);
std::string describe(const PlanStatusData& status);

}  // namespace skyroute::cli
