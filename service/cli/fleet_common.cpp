#include "service/cli/fleet_common.hpp"

#include <cstdio>
#include <cstring>

#include "service/mission_json.hpp"
#include "service/trajectory_export.hpp"

namespace skyroute::cli {

namespace {

// --vehicles: "ID@LAT,LON,ALT" items, or plain "LAT,LON,ALT" ones named uav-1 .. uav-N.
void parseVehicles(const std::string& tool, const std::string& text, FleetRequestData& f) {
  const std::vector<std::string> items = splitList(text);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::string field = "--vehicles[" + std::to_string(i) + "]";
    const auto at = items[i].find('@');
    std::string id = at == std::string::npos ? "uav-" + std::to_string(i + 1) : items[i].substr(0, at);
    id.erase(id.find_last_not_of(" \t") + 1);
    if (id.empty()) fail(tool, kExitUsage, field + " '" + items[i] + "': the vehicle id before '@' is empty");
    auto p = parseGeoTriple(at == std::string::npos ? items[i] : items[i].substr(at + 1), field);
    if (!p) fail(tool, kExitUsage, p.error().message);
    f.vehicle_ids.push_back(id);
    f.begins.push_back(*p);
  }
}

}  // namespace

FleetRequestData buildFleetRequest(const std::string& tool, const FleetInputArgs& a,
                                   const std::string& default_request_id) {
  FleetRequestData f;
  if (!a.file.empty()) {
    if (!a.vehicles.empty() || !a.tasks.empty() || !a.ends.empty()) {
      fail(tool, kExitUsage, "--file gives the vehicles, tasks and ends: leave out --vehicles, --tasks and --ends");
    }
    auto parsed = fleetFromJson(readJsonFile(tool, "--file", a.file));
    if (!parsed) fail(tool, kExitBadInput, "--file " + a.file + ": " + parsed.error().message);
    f = std::move(*parsed);
  } else {
    if (a.vehicles.empty() || a.tasks.empty()) fail(tool, kExitUsage, "give --file FLEET.json, or --vehicles and --tasks");
    parseVehicles(tool, a.vehicles, f);
    f.tasks = parseListOption(tool, "--tasks", a.tasks, &parseGeoTriple);
    f.ends = a.ends.empty() ? f.begins : parseListOption(tool, "--ends", a.ends, &parseGeoTriple);
  }
  applyVehicleLimits(a.limits, f.limits);
  if (!a.request_id.empty()) f.request_id = a.request_id;
  if (f.request_id.empty()) f.request_id = default_request_id;
  return f;
}

void checkFleetRequest(const std::string& tool, const FleetInputArgs& args, const FleetRequestData& request,
                       const FleetMissionOptions& options) {
  if (auto bad = validateFleetRequest(request, options)) {
    fail(tool, fleetInputExitCode(args, bad->field),
         fleetUserField(args, bad->field) + ": " + bad->message + " [" + std::string(to_string(bad->code)) + "]");
  }
}

std::string fleetUserField(const FleetInputArgs& a, const std::string& field) {
  if (const std::string option = givenLimitOption(a.limits, field); !option.empty()) return option;
  if (field == "request_id" && !a.request_id.empty()) return "--request-id";
  if (field.empty()) return field;
  if (!a.file.empty()) return "--file " + a.file + ": " + field;
  // Without --ends, the ends are the begins: --vehicles gave them.
  const std::pair<const char*, const char*> kLists[] = {
      {"vehicle_ids", "--vehicles"}, {"begins", "--vehicles"}, {"tasks", "--tasks"},
      {"ends", a.ends.empty() ? "--vehicles" : "--ends"}};
  for (const auto& [prefix, option] : kLists) {
    if (field.rfind(prefix, 0) == 0) return option + field.substr(std::strlen(prefix));
  }
  const std::string limit = limitSource(a.limits, field);
  return limit.empty() ? field : limit;
}

int fleetInputExitCode(const FleetInputArgs& a, const std::string& field) {
  return fleetUserField(a, field).rfind("--file ", 0) == 0 ? kExitBadInput : kExitUsage;
}

bool isFleetInputError(PlanErrorCode code) {
  switch (code) {
    case PlanErrorCode::kInvalidArgument:
    case PlanErrorCode::kUnknownPlanner:
    case PlanErrorCode::kEmptyMission:
    case PlanErrorCode::kMissionTooLarge:
    case PlanErrorCode::kLimitsOutOfRange:
    case PlanErrorCode::kOutsideMap:
    case PlanErrorCode::kUnderGround: return true;
    default: return false;
  }
}

void printFleetOutcome(const FleetRequestData& request, const FleetStatusData& status,
                       const std::vector<TrajectoryData>& trajectories) {
  std::printf("fleet %s: %zu vehicles, %zu tasks, planned in %.2f s\n", request.request_id.c_str(),
              request.vehicle_ids.size(), request.tasks.size(), status.planning_time_s);
  for (std::size_t i = 0; i < status.allocation.size(); ++i) {
    const FleetVehicleAllocationData& v = status.allocation[i];
    std::string tasks;
    for (std::uint32_t t : v.tasks) tasks += (tasks.empty() ? "" : ", ") + std::to_string(t);
    std::printf("  %s: tasks %s; start delay %.1f s", v.vehicle_id.c_str(), tasks.empty() ? "none" : tasks.c_str(),
                v.delay_s);
    if (i < trajectories.size() && trajectories[i].vehicle_id == v.vehicle_id && !trajectories[i].samples.empty()) {
      const auto& s = trajectories[i].samples;
      std::printf("; flight %.1f s, %zu samples", s.back().t_rel_s - s.front().t_rel_s, s.size());
    }
    std::printf("\n");
  }
  std::printf("makespan %.1f s (%d grid steps)\n", status.makespan_s, status.makespan_steps);
  std::printf("separation %.1f m achieved, %.1f m required; %u vehicle start%s delayed\n",
              status.achieved_separation_m, status.min_separation_m, status.separation_repairs,
              status.separation_repairs == 1 ? "" : "s");
}

Rgb vehicleRgb(std::size_t index) {
  const std::string hex = vehicleColourHex(index);  // "#RRGGBB"
  auto channel = [&](int k) { return static_cast<std::uint8_t>(std::stoi(hex.substr(1 + 2 * k, 2), nullptr, 16)); };
  return Rgb{channel(0), channel(1), channel(2)};
}

const std::vector<std::string>& fleetTrajectoryFormats() {
  static const std::vector<std::string> kFormats = {"csv", "geojson", "kml"};
  return kFormats;
}

void writeFleetTrajectories(const std::string& tool, const std::string& path,
                            const std::vector<TrajectoryData>& trajectories) {
  const std::string ext = lowerExtension(path);
  const Status written = ext == "csv"       ? writeTrajectoriesCsv(path, trajectories)
                         : ext == "geojson" ? writeTrajectoriesOgr(path, "GeoJSON", trajectories)
                                            : writeTrajectoriesOgr(path, "KML", trajectories);
  if (!written.ok()) fail(tool, kExitUsage, "--out " + written.error().describe());
  std::printf("wrote %zu trajectories to %s\n", trajectories.size(), path.c_str());
}

}  // namespace skyroute::cli
