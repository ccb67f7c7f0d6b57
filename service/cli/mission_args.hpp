// The points and limits of one mission as `skyroute plan` and `skyroute mission` take them: a
// mission file (the JSON `skyroute request --file` publishes) and/or --from/--via/--to in
// LAT,LON,ALT, the vehicle-limit options overriding the file's values.
#pragma once

#include <string>
#include <vector>

#include "service/cli/cli_common.hpp"
#include "service/mission_types.hpp"

namespace skyroute::cli {

struct MissionPointArgs {
  std::string mission_file;      // --mission
  std::string from;              // --from LAT,LON,ALT
  std::string to;                // --to
  std::vector<std::string> via;  // --via, in the given order
  bool fixed_order = false;      // --fixed-order
  VehicleLimitArgs limits;
};

// The mission: the file's (kExitBadInput naming it when unreadable or invalid), with the options
// on top (kExitUsage naming the option when malformed). Without a file, --from and --to are
// required. Ids are left as the file has them.
MissionRequestData buildMissionRequest(const std::string& tool, const MissionPointArgs& args);

// Whether a request field holds the mission file's value (no option overrode it).
bool fieldFromFile(const MissionPointArgs& args, const std::string& field);
// A request field as the user wrote it: the mission file's field ("--mission F: points[1]"), or
// the option that set it ("--via[1]", "--clearance-m").
std::string missionUserField(const MissionPointArgs& args, const std::string& field);
// The exit code of a request that the pipeline's validate stage refused because of `field`: an
// invalid input file (kExitBadInput), or a bad option value (kExitUsage).
int validationExitCode(const MissionPointArgs& args, const std::string& field);

}  // namespace skyroute::cli
