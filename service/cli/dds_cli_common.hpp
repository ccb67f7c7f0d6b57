// What the DDS tools share: opening a participant (with the identity folder of --security, see
// dds_commands.hpp) or failing with a message and exit code, stopping a waitset on SIGINT/SIGTERM,
// and one-line descriptions of what arrives.
#pragma once

#include <string>

#include "planning/core/result.hpp"
#include "service/cli/cli_common.hpp"
#include "service/dds/dds_entities.hpp"
#include "service/mission_types.hpp"

namespace skyroute::cli {

// An identity folder that fails its checks, or that DDS Security refuses, exits 3 naming the file
// or the reason; a domain out of range exits 2.
dds::Entity openParticipant(const std::string& tool, int domain);

// SIGINT and SIGTERM trigger this waitset (only that, as the Cyclone examples do).
void stopOnSignals(dds_entity_t waitset);

std::string describe(const TrajectoryData& trajectory);
std::string describe(const PlanStatusData& status);

}  // namespace skyroute::cli
