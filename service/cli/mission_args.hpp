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
  std::string file_option = "--mission";  // the option that names the mission file, in messages
  std::string mission_file;      // that option's value
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

// Fails with a pipeline error: the field as the user wrote it (the mission file's field, or the
// option that set it: "--via[1]", "--clearance-m"), the reason, the code and the stage. A request
// the validate stage refused is the input's fault (kExitBadInput for the file's values, kExitUsage
// for an option's), any later failure a failed plan.
[[noreturn]] void failPlanError(const std::string& tool, const MissionPointArgs& args, const PlanError& error);

}  // namespace skyroute::cli
