#include "service/cli/height_ref_option.hpp"

#include <fstream>
#include <iostream>
#include <optional>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "service/cli/cli_common.hpp"
#include "service/height_datum.hpp"
#include "service/mission_heights.hpp"

namespace skyroute::cli {

namespace {

// The mission file's own height_ref (the caller has already read the file as a mission).
std::optional<HeightReference> fileHeightReference(const std::string& tool, const std::string& mission_file) {
  if (mission_file.empty()) return std::nullopt;
  std::ifstream in(mission_file);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  auto reference = missionHeightReferenceFromJson(j);
  if (!reference) fail(tool, kExitBadInput, mission_file + ": " + reference.error().describe());
  return *reference;
}

}  // namespace

void addHeightRefOption(CLI::App& cmd, HeightRefArgs& args) {
  cmd.add_option("--height-ref", args.value,
                 "What the points' heights are measured from: amsl (the EGM96 geoid) or ellipsoid (WGS 84, as "
                 "GNSS gives them; converted to AMSL with EGM96). Default: the mission file's height_ref, else amsl")
      ->check(CLI::Validator(
          [](std::string& value) {
            return parseHeightReference(value) ? std::string()
                                               : "'" + value + "' is not a height reference: use amsl or ellipsoid";
          },
          "amsl|ellipsoid"));
}

MissionRequestData missionInAmsl(const std::string& tool, const HeightRefArgs& args, const std::string& mission_file,
                                 MissionRequestData mission) {
  const std::optional<HeightReference> from_file = fileHeightReference(tool, mission_file);
  std::optional<HeightReference> from_option;
  if (!args.value.empty()) {
    from_option = parseHeightReference(args.value);
    if (!from_option) fail(tool, kExitUsage, "--height-ref '" + args.value + "': use amsl or ellipsoid");
  }
  if (from_option && from_file && *from_option != *from_file) {
    fail(tool, kExitUsage,
         "--height-ref " + args.value + " disagrees with the mission file's height_ref " +
             std::string(to_string(*from_file)) + " (" + mission_file + "): one reference holds for every point");
  }
  const HeightReference reference = from_option ? *from_option : from_file.value_or(HeightReference::kAmsl);
  if (reference == HeightReference::kAmsl) return mission;

  auto converter = InputHeightConverter::create(reference);
  if (!converter) fail(tool, kExitBadInput, "--height-ref " + std::string(to_string(reference)) + ": " +
                                                converter.error().describe());
  if (Status s = convertMissionHeightsToAmsl(mission, *converter); !s.ok()) {
    fail(tool, kExitUsage, "--height-ref " + std::string(to_string(reference)) + ": " + s.error().describe());
  }
  std::cerr << "heights: WGS 84 ellipsoidal heights converted to AMSL with the EGM96 geoid" << std::endl;
  return mission;
}

}  // namespace skyroute::cli
