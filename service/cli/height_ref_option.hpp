// `--height-ref amsl | ellipsoid`, shared by the commands that take a mission (plan, request):
// which surface the heights of the mission's LAT,LON,ALT points are measured from. One reference
// holds for every point, from the options and from a mission file alike; a mission file may name
// it with "height_ref", and the option must then agree. Ellipsoidal heights become AMSL (EGM96
// through PROJ, service/height_datum.hpp) before the mission goes anywhere.
#pragma once

#include <string>

#include "service/mission_types.hpp"

namespace CLI {
class App;
}

namespace skyroute::cli {

struct HeightRefArgs {
  std::string value;  // "" = not given: the mission file's height_ref, else amsl
};

// Adds the option; a value other than amsl or ellipsoid is a usage error naming it.
void addHeightRefOption(CLI::App& cmd, HeightRefArgs& args);

// The mission with every LAT,LON,ALT height in AMSL. mission_file is the mission JSON the mission
// came from ("" = none). Fails with kExitUsage when the option and the file disagree or a point
// is in ENU with an ellipsoidal reference, kExitBadInput for a bad height_ref in the file or a
// missing geoid grid.
MissionRequestData missionInAmsl(const std::string& tool, const HeightRefArgs& args, const std::string& mission_file,
                                 MissionRequestData mission);

}  // namespace skyroute::cli
