// What `skyroute fleet` shares between planning here (the mission pipeline's fleet stage) and
// asking a running skyrouted over DDS (--domain): the fleet request from --file or from
// --vehicles/--tasks/--ends, its fields named as the user wrote them, the printed outcome and the
// trajectory files.
#pragma once

#include <string>
#include <vector>

#include "service/cli/cli_common.hpp"
#include "service/fleet_mission.hpp"
#include "service/map_image.hpp"
#include "service/mission_types.hpp"

namespace skyroute::cli {

struct FleetInputArgs {
  std::string file;        // --file FLEET.json
  std::string vehicles;    // --vehicles "ID@LAT,LON,ALT;..." or "LAT,LON,ALT;..."
  std::string tasks;       // --tasks "LAT,LON,ALT;..."
  std::string ends;        // --ends "LAT,LON,ALT;..." (default: each vehicle's begin)
  std::string request_id;  // --request-id
  VehicleLimitArgs limits;
};

// The request: the file's (kExitBadInput naming it when unreadable or invalid) or the options'
// (kExitUsage naming the option and item), limits and request id from the options on top. The
// request id defaults to `default_request_id`.
FleetRequestData buildFleetRequest(const std::string& tool, const FleetInputArgs& args,
                                   const std::string& default_request_id);

// The structural checks of the fleet stage (validateFleetRequest) before any work: a problem fails
// with its field named as the user wrote it.
void checkFleetRequest(const std::string& tool, const FleetInputArgs& args, const FleetRequestData& request,
                       const FleetMissionOptions& options = {});

// A request field as the user wrote it ("--file F: tasks[3].lat_deg", "--tasks[3]",
// "--max-speed-mps") and the exit code of a request refused because of it (kExitBadInput for the
// file's, kExitUsage for an option's).
std::string fleetUserField(const FleetInputArgs& args, const std::string& field);
int fleetInputExitCode(const FleetInputArgs& args, const std::string& field);
// Whether a failed fleet plan failed because of its input (a point outside the DEM or under the
// ground, a bad value) rather than in planning.
bool isFleetInputError(PlanErrorCode code);

// The outcome: per vehicle its tasks and start delay (and, with trajectories in request order, its
// flight time), the makespan and the separation.
void printFleetOutcome(const FleetRequestData& request, const FleetStatusData& status,
                       const std::vector<TrajectoryData>& trajectories);

// The index-th vehicle's colour in pictures, the same as in its KML line (vehicleColourHex).
Rgb vehicleRgb(std::size_t index);

// --out of the 3D fleet: .csv, .geojson or .kml, the writers (and columns) of `skyroute gcs`.
const std::vector<std::string>& fleetTrajectoryFormats();
void writeFleetTrajectories(const std::string& tool, const std::string& path,
                            const std::vector<TrajectoryData>& trajectories);

}  // namespace skyroute::cli
