#include "service/cli/mission_args.hpp"

#include "service/mission_json.hpp"

namespace skyroute::cli {

MissionRequestData buildMissionRequest(const std::string& tool, const MissionPointArgs& a) {
  MissionRequestData m;
  if (!a.mission_file.empty()) {
    auto parsed = missionFromJson(readJsonFile(tool, a.file_option, a.mission_file));
    if (!parsed) fail(tool, kExitBadInput, a.file_option + " " + a.mission_file + ": " + parsed.error().message);
    m = std::move(*parsed);
  } else if (a.from.empty() || a.to.empty()) {
    fail(tool, kExitUsage, "give " + a.file_option + " FILE, or --from and --to (and any --via)");
  }
  auto point = [&](const std::string& text, const std::string& option) {
    auto p = parseGeoTriple(text, option);
    if (!p) fail(tool, kExitUsage, p.error().message);
    return *p;
  };
  if (!a.from.empty()) m.begin = point(a.from, "--from");
  if (!a.to.empty()) m.end = point(a.to, "--to");
  if (!a.via.empty()) {
    m.points.clear();
    for (std::size_t i = 0; i < a.via.size(); ++i) m.points.push_back(point(a.via[i], "--via[" + std::to_string(i) + "]"));
  }
  if (a.fixed_order) m.fixed_order = true;
  applyVehicleLimits(a.limits, m.limits);
  return m;
}

namespace {

// Whether a request field holds the mission file's value (no option overrode it).
bool fieldFromFile(const MissionPointArgs& a, const std::string& field) {
  if (a.mission_file.empty()) return false;
  if (field == "begin") return a.from.empty();
  if (field == "end") return a.to.empty();
  if (field.rfind("points[", 0) == 0) return a.via.empty();
  return givenLimitOption(a.limits, field).empty();
}

// A request field as the user wrote it.
std::string missionUserField(const MissionPointArgs& a, const std::string& field) {
  if (fieldFromFile(a, field)) return a.file_option + " " + a.mission_file + ": " + field;
  if (field == "begin") return "--from";
  if (field == "end") return "--to";
  if (field.rfind("points[", 0) == 0) return "--via[" + field.substr(7);
  if (field == "planner") return "--planner";
  const std::string limit = limitSource(a.limits, field);
  return limit.empty() ? field : limit;
}

int validationExitCode(const MissionPointArgs& a, const std::string& field) {
  return fieldFromFile(a, field) ? kExitBadInput : kExitUsage;
}

}  // namespace

void failPlanError(const std::string& tool, const MissionPointArgs& a, const PlanError& e) {
  const int code = e.stage == PlanStage::kValidate ? validationExitCode(a, e.field) : kExitPlanningFailed;
  fail(tool, code,
       missionUserField(a, e.field) + ": " + e.message + " [" + std::string(to_string(e.code)) + ", stage " +
           std::string(to_string(e.stage)) + "]");
}

}  // namespace skyroute::cli
