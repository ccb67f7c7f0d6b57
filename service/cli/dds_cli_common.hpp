// What the DDS tools share: opening a participant (or failing with a message and exit code),
// stopping a waitset on SIGINT/SIGTERM, and parsing "LAT,LON,ALT" arguments.
#pragma once

#include <string>

#include "planning/core/result.hpp"
#include "service/dds/dds_entities.hpp"
#include "service/mission_types.hpp"

namespace skyroute::cli {

// Exit codes of the DDS tools.
inline constexpr int kExitFailure = 1;      // the service answered with a failure, or too few samples
inline constexpr int kExitBadInput = 2;     // an argument or file is malformed
inline constexpr int kExitNoService = 3;    // nothing answered in time
inline constexpr int kExitDdsError = 4;

// Prints "skyroute <tool>: <message>" on stderr and throws CLI::RuntimeError(code).
[[noreturn]] void fail(const std::string& tool, int code, const std::string& message);

dds::Entity openParticipant(const std::string& tool, int domain);

// SIGINT and SIGTERM trigger this waitset (only that, as the Cyclone examples do).
void stopOnSignals(dds_entity_t waitset);

// "LAT,LON,ALT" in degrees and metres AMSL; field names the option in errors.
Result<MissionPointData> parseGeoTriple(const std::string& text, const std::string& field);

std::string describe(const TrajectoryData& trajectory);
std::string describe(const PlanStatusData& status);

}  // namespace skyroute::cli
