// Fuzzes the mission file (`skyroute request --file`): JSON text -> missionFromJson, then what an
// accepted mission meets next: the service's structural checks (validateMissionRequest with the
// daemon's bounds) and the trip to the daemon (toWire -> fromWire). Reading back the mission's own
// JSON or wire form must give the same mission; anything else is a finding (abort).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <string_view>

#include <nlohmann/json.hpp>

#include "service/dds/conversions.hpp"
#include "service/engine.hpp"
#include "service/mission_json.hpp"
#include "tests/fuzz/finding.hpp"
#include "tests/fuzz/mission_equal.hpp"

namespace {

[[noreturn]] void finding(const std::string& what) { skyroute::fuzz::reportFinding("mission_json_fuzzer", what); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skyroute;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return 0;
  auto parsed = missionFromJson(j);
  if (!parsed) {
    if (parsed.error().field.empty()) finding("a rejected mission names no field");
    return 0;
  }
  MissionRequestData mission = std::move(*parsed);
  // As `skyroute request` does: the command line fills in missing ids.
  if (mission.vehicle_id.empty()) mission.vehicle_id = "uav";
  if (mission.request_id.empty()) mission.request_id = "request";
  const auto problem = validateMissionRequest(mission, EngineOptions{}.pipeline.bounds);
  if (problem && problem->field.empty()) finding("a refused mission names no field");

  auto again = missionFromJson(missionToJson(mission));
  if (!again || !fuzz::sameMission(*again, mission)) finding("the mission's own JSON reads back differently");

  dds::WireSample<skyroute_msgs_MissionRequest> wire(&skyroute_msgs_MissionRequest_desc);
  dds::toWire(mission, wire.msg());
  auto received = dds::fromWire(wire.msg());
  // The daemon's node refuses some of what the service's checks refuse (ids outside their
  // bounds, before anything else); `skyroute request` sends nothing they refuse.
  if (!received) {
    if (!problem) finding("the daemon refuses a mission the service's checks accept: " + received.error().describe());
  } else if (!fuzz::sameMission(*received, mission)) {
    finding("the mission arrives changed over DDS");
  }
  return 0;
}
