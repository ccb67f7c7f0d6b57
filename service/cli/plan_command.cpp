// skyroute plan: one mission through the mission pipeline (the daemon's own), written out as the
// daemon would publish it. The mission comes from a mission file (the JSON `skyroute request
// --file` publishes) or from --from/--via/--to; the configuration from --config (skyrouted's keys).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "service/cli/cli_common.hpp"
#include "service/cli/commands.hpp"
#include "service/cli/height_ref_option.hpp"
#include "service/map_image.hpp"
#include "service/mission_json.hpp"
#include "service/mission_pipeline.hpp"
#include "service/qgc_plan.hpp"
#include "service/trajectory_export.hpp"

namespace skyroute::cli {
namespace {

const std::string kTool = "plan";

struct PlanArgs {
  ConfigArgs config;
  std::optional<std::string> dem;
  std::string mission_file;
  std::string from;
  std::string to;
  std::vector<std::string> via;
  std::string vehicle;
  std::string planner;
  bool fixed_order = false;
  std::optional<std::uint64_t> seed;
  std::optional<std::uint64_t> iterations;
  std::optional<double> budget_s;
  std::optional<double> dt_s;
  // Vehicle limits: override the mission file's (or the defaults).
  std::optional<double> clearance_m, ceiling_m, vref_mps, max_speed_mps, max_accel_mps2, max_climb_mps,
      max_descent_mps, min_turn_radius_m;
  std::string out;
  std::string png;
  HeightRefArgs height_ref;
};

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// Output paths are checked before any work: a known format and a folder that exists.
void checkOutputPath(const std::string& option, const std::string& path, const std::vector<std::string>& formats) {
  if (path.empty()) return;
  const std::string ext = lowerExtension(path);
  if (std::find(formats.begin(), formats.end(), ext) == formats.end()) {
    std::string known;
    for (const auto& f : formats) known += (known.empty() ? "." : ", .") + f;
    fail(kTool, kExitUsage, option + " " + path + ": unknown format '." + ext + "' (use " + known + ")");
  }
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  if (!folder.empty() && !std::filesystem::is_directory(folder)) {
    fail(kTool, kExitUsage, option + " " + path + ": the folder " + folder.string() + " does not exist");
  }
}

MissionRequestData buildMission(const PlanArgs& a) {
  MissionRequestData m;
  if (!a.mission_file.empty()) {
    std::ifstream in(a.mission_file);
    if (!in) fail(kTool, kExitBadInput, "--mission " + a.mission_file + ": cannot open the mission file");
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_discarded()) fail(kTool, kExitBadInput, "--mission " + a.mission_file + ": not valid JSON");
    auto parsed = missionFromJson(j);
    if (!parsed) fail(kTool, kExitBadInput, "--mission " + a.mission_file + ": " + parsed.error().describe());
    m = std::move(*parsed);
  } else if (a.from.empty() || a.to.empty()) {
    fail(kTool, kExitUsage, "give --mission FILE, or --from and --to (and any --via)");
  }
  auto point = [&](const std::string& text, const std::string& option) {
    auto p = parseGeoTriple(text, option);
    if (!p) fail(kTool, kExitUsage, p.error().message);
    return *p;
  };
  if (!a.from.empty()) m.begin = point(a.from, "--from");
  if (!a.to.empty()) m.end = point(a.to, "--to");
  if (!a.via.empty()) {
    m.points.clear();
    for (std::size_t i = 0; i < a.via.size(); ++i) m.points.push_back(point(a.via[i], "--via[" + std::to_string(i) + "]"));
  }
  if (!a.vehicle.empty()) m.vehicle_id = a.vehicle;
  if (m.vehicle_id.empty()) m.vehicle_id = "uav-1";
  if (m.request_id.empty()) m.request_id = m.vehicle_id + "-plan";
  if (!a.planner.empty()) m.planner = a.planner;
  if (a.fixed_order) m.fixed_order = true;
  VehicleLimitsData& l = m.limits;
  const std::pair<const std::optional<double>*, double*> limits[] = {
      {&a.clearance_m, &l.min_clearance_agl_m}, {&a.ceiling_m, &l.ceiling_amsl_m},
      {&a.vref_mps, &l.v_ref_mps},               {&a.max_speed_mps, &l.max_speed_mps},
      {&a.max_accel_mps2, &l.max_accel_mps2},   {&a.max_climb_mps, &l.max_climb_rate_mps},
      {&a.max_descent_mps, &l.max_descent_rate_mps}, {&a.min_turn_radius_m, &l.min_turn_radius_m}};
  for (const auto& [option, field] : limits) {
    if (*option) *field = **option;
  }
  return m;
}

// A request field as the user wrote it: the command line's options, or the mission file's field.
std::string userField(const PlanArgs& a, const std::string& field) {
  if (!a.mission_file.empty()) return "--mission " + a.mission_file + ": " + field;
  if (field == "begin") return "--from";
  if (field == "end") return "--to";
  if (field.rfind("points[", 0) == 0) return "--via[" + field.substr(7);
  static const std::pair<const char*, const char*> kLimitOptions[] = {
      {"limits.min_clearance_agl_m", "--clearance-m"}, {"limits.ceiling_amsl_m", "--ceiling-m"},
      {"limits.v_ref_mps", "--vref-mps"},              {"limits.max_speed_mps", "--max-speed-mps"},
      {"limits.max_accel_mps2", "--max-accel-mps2"},   {"limits.max_climb_rate_mps", "--max-climb-mps"},
      {"limits.max_descent_rate_mps", "--max-descent-mps"}, {"limits.min_turn_radius_m", "--min-turn-radius-m"},
      {"planner", "--planner"}};
  for (const auto& [name, option] : kLimitOptions) {
    if (field == name) return option;
  }
  return field;
}

void writePng(const std::string& path, const WorldModel& world, const MissionPlan& plan, const TrajectoryData& data) {
  auto image = MapImage::hillshade(world.terrain().dem());
  if (!image.ok()) fail(kTool, kExitUsage, "--png " + image.error().describe());
  const Heightfield& terrain = world.terrain();
  std::vector<Eigen::Vector3d> flown;
  std::vector<double> altitude;
  std::vector<double> ground;
  for (const TrajectorySampleData& s : data.samples) {
    flown.push_back(s.position_enu_m);
    altitude.push_back(s.position_enu_m.z());
    ground.push_back(terrain.heightAt(s.position_enu_m.x(), s.position_enu_m.y()));
  }
  const PlannedRoute& route = plan.flight->route();
  for (const RouteLeg& leg : route.legs) image->drawPathEn(terrain, leg.rrt.path_m, Rgb{250, 250, 120}, 1);
  image->drawPathEn(terrain, flown, Rgb{220, 20, 20}, 3);
  for (const Eigen::Vector3d& p : plan.mission.ordered_m) image->drawDisc(terrain.enToPixel(p.x(), p.y()), 5, Rgb{20, 20, 220});
  image->appendProfile(altitude, ground, std::max(120, image->height() / 4));
  Status saved = image->savePng(path);
  if (!saved.ok()) fail(kTool, kExitUsage, "--png " + saved.error().describe());
}

void writeJson(const std::string& path, const MissionPlan& plan, const TrajectoryData& data) {
  const BuiltTrajectory& built = plan.flight->route().built;
  nlohmann::json j;
  j["vehicle_id"] = data.vehicle_id;
  j["planner"] = plan.mission.planner->name;
  j["seed"] = plan.seed;
  j["duration_s"] = built.trajectory.duration_s();
  j["status"] = to_string(built.report.status);
  j["visiting_order"] = data.visiting_order;
  j["notes"] = plan.notes;
  for (const auto& leg : data.legs) {
    j["legs"].push_back({{"from", leg.from_point}, {"to", leg.to_point}, {"start_s", leg.start_s}, {"end_s", leg.end_s}});
  }
  for (const auto& s : data.samples) {
    j["samples"].push_back({{"time_s", s.t_rel_s},
                            {"lat_deg", s.geo.lat_deg},
                            {"lon_deg", s.geo.lon_deg},
                            {"alt_amsl_m", s.geo.alt_amsl_m},
                            {"enu_m", {s.position_enu_m.x(), s.position_enu_m.y(), s.position_enu_m.z()}},
                            {"velocity_mps", {s.velocity_enu_mps.x(), s.velocity_enu_mps.y(), s.velocity_enu_mps.z()}},
                            {"heading_deg", s.heading_deg}});
  }
  std::ofstream out(path);
  if (!out) fail(kTool, kExitUsage, "--out " + path + ": cannot write");
  out << j.dump(1) << "\n";
}

void printSummary(const MissionPlan& plan, const TrajectoryData& data) {
  const PlannedRoute& route = plan.flight->route();
  double searched_m = 0.0;
  double shortened_m = 0.0;
  for (const RouteLeg& leg : route.legs) {
    searched_m += leg.rrt.length_m;
    shortened_m += leg.lospo_length_m;
  }
  std::string order;
  for (std::uint32_t k : data.visiting_order) order += (order.empty() ? "" : ",") + std::to_string(k);
  std::printf("order: %s (%s)\n", order.c_str(), plan.mission.ordering.method.c_str());
  std::printf("route: %zu legs with %s, searched %.0f m, shortened %.0f m, %zu waypoints\n", route.legs.size(),
              std::string(plan.mission.planner->name).c_str(), searched_m, shortened_m, route.waypoints_m.size());
  const auto& report = route.built.report;
  std::printf("trajectory: %.1f s, %s, max speed %.1f m/s, max accel %.2f m/s^2, %zu samples, planned in %.2f s\n",
              route.built.trajectory.duration_s(), std::string(to_string(report.status)).c_str(),
              report.final_check.max_speed_mps, report.final_check.max_accel_mps2, data.samples.size(),
              plan.planning_time_s);
  for (const std::string& repair : report.repairs) std::printf("  repair: %s\n", repair.c_str());
  for (const std::string& note : plan.notes) std::printf("  note: %s\n", note.c_str());
}

void runPlan(const PlanArgs& a) {
  DaemonConfig config = loadConfig(kTool, a.config);
  if (a.dem) config.dem_path = *a.dem;
  PipelineOptions& p = config.engine.pipeline;
  if (a.seed) p.seed = *a.seed;
  if (a.iterations) p.budget.leg_max_iterations = *a.iterations;
  if (a.budget_s) p.budget.leg_time_cap_s = *a.budget_s;
  if (a.dt_s) p.sample_dt_s = *a.dt_s;
  if (auto bad = validatePipelineOptions(p)) fail(kTool, kExitUsage, bad->describe());
  if (printConfigIfAsked(a.config, config)) return;
  checkOutputPath("--out", a.out, {"csv", "geojson", "json", "plan", "waypoints"});
  checkOutputPath("--png", a.png, {"png"});
  const MissionRequestData mission = missionInAmsl(kTool, a.height_ref, a.mission_file, buildMission(a));

  const std::string dem = demPathOf(kTool, config);
  std::cerr << "loading " << dem << " ..." << std::endl;
  auto world = WorldModel::load(dem, config.world);
  if (!world.ok()) fail(kTool, kExitBadInput, "terrain.dem " + world.error().describe());
  const MissionPipeline pipeline(*world, p);
  auto progress = [](PlanStage, const std::string& what) { std::cerr << what << " ..." << std::endl; };
  auto planned = pipeline.plan(PipelineRequest{mission, std::nullopt, std::nullopt},
                               static_cast<double>(utcNowNs()) * 1e-9, {}, progress);
  if (!planned.ok()) {
    const PlanError& e = planned.error();
    // A request that cannot be planned at all is the input's fault: the options', or the file's.
    const int input_code = a.mission_file.empty() ? kExitUsage : kExitBadInput;
    const int code = e.stage == PlanStage::kValidate ? input_code : kExitPlanningFailed;
    fail(kTool, code,
         userField(a, e.field) + ": " + e.message + " [" + std::string(to_string(e.code)) + ", stage " +
             std::string(to_string(e.stage)) + "]");
  }
  const MissionPlan& plan = *planned;
  const TrajectoryData data = pipeline.sample(
      plan, TrajectoryIdentity{mission.vehicle_id, mission.vehicle_id + "-plan", 0, mission.request_id});
  printSummary(plan, data);

  if (!a.out.empty()) {
    const std::string ext = lowerExtension(a.out);
    Status written = Status::success();
    if (ext == "csv") {
      written = writeTrajectoriesCsv(a.out, {data});
    } else if (ext == "geojson") {
      written = writeTrajectoriesOgr(a.out, "GeoJSON", {data});
    } else if (ext == "plan" || ext == "waypoints") {
      auto qgc = qgcMissionFromTrajectory(data);
      if (!qgc.ok()) fail(kTool, kExitPlanningFailed, "--out " + qgc.error().describe());
      written = ext == "plan" ? writeQgcPlan(a.out, *qgc) : writeQgcWaypoints(a.out, *qgc);
    } else {
      writeJson(a.out, plan, data);
    }
    if (!written.ok()) fail(kTool, kExitUsage, "--out " + written.error().describe());
    std::printf("wrote %zu samples to %s\n", data.samples.size(), a.out.c_str());
  }
  if (!a.png.empty()) {
    writePng(a.png, **world, plan, data);
    std::printf("wrote %s\n", a.png.c_str());
  }
}

}  // namespace

void addPlanCommand(CLI::App& app) {
  auto a = std::make_shared<PlanArgs>();
  CLI::App* plan = app.add_subcommand(
      "plan", "Plan one mission as skyrouted would: MMD*L order, each leg's path, a checked 7th-order trajectory");
  plan->footer(std::string("Example:\n  skyroute plan --mission data/missions/demo_mission.json --out out/plan.csv\n  "
                           "skyroute plan --from 44.27,-71.35,1500 --to 44.30,-71.28,1600 --png out/plan.png\n\n") +
               std::string(kExitCodeTable));
  addConfigOptions(*plan, a->config);
  plan->add_option("--dem", a->dem, "DEM file (config terrain.dem; default: the embedded terrain)");
  plan->add_option("--mission", a->mission_file,
                   "Mission JSON, as `skyroute request --file` publishes it (docs/dds.md); options below override it");
  plan->add_option("--from", a->from, "Start LAT,LON,ALT (degrees, degrees, metres AMSL)");
  plan->add_option("--to", a->to, "Goal LAT,LON,ALT");
  plan->add_option("--via", a->via, "Mission point LAT,LON,ALT (repeatable); MMD*L orders them unless --fixed-order");
  plan->add_flag("--fixed-order", a->fixed_order, "Visit the points in the given order");
  addHeightRefOption(*plan, a->height_ref);
  plan->add_option("--vehicle", a->vehicle, "Vehicle id (default: the mission's, else uav-1)");
  plan->add_option("--planner", a->planner,
                   "Route planner: " + routePlannerNames(" | ") + " (default: config planning.default_planner)");
  plan->add_option("--seed", a->seed, "Seed of the plan (config planning.seed, default 1)");
  plan->add_option("--iterations", a->iterations, "Search iterations per leg (config planning.leg_max_iterations)");
  plan->add_option("--budget-s", a->budget_s,
                   "Wall-clock cap per leg, seconds; 0 = none (config planning.leg_time_cap_s)")
      ->check(CLI::Range(0.0, 3600.0));
  plan->add_option("--dt", a->dt_s, "Sample spacing of the output, seconds (config planning.sample_dt_s)")
      ->check(CLI::Range(0.001, 10.0));
  plan->add_option("--clearance-m", a->clearance_m, "Minimum height above ground, m (limits.min_clearance_agl_m, default 30)");
  plan->add_option("--ceiling-m", a->ceiling_m, "Highest altitude, m AMSL (limits.ceiling_amsl_m, default 5000)");
  plan->add_option("--vref-mps", a->vref_mps, "Cruise speed V_ref, m/s (limits.v_ref_mps, default 20)");
  plan->add_option("--max-speed-mps", a->max_speed_mps, "Speed limit, m/s (limits.max_speed_mps, default 30)");
  plan->add_option("--max-accel-mps2", a->max_accel_mps2, "Acceleration limit, m/s^2 (limits.max_accel_mps2, default 4)");
  plan->add_option("--max-climb-mps", a->max_climb_mps, "Climb rate limit, m/s (limits.max_climb_rate_mps, default 5)");
  plan->add_option("--max-descent-mps", a->max_descent_mps,
                   "Descent rate limit, m/s (limits.max_descent_rate_mps, default 4)");
  plan->add_option("--min-turn-radius-m", a->min_turn_radius_m,
                   "Minimum turn radius, m; 0 = none (limits.min_turn_radius_m, default 0)");
  plan->add_option("--out", a->out,
                   "Write the trajectory: .csv (the columns of skyroute gcs --csv), .geojson, .json, or a "
                   "QGroundControl .plan / .waypoints");
  plan->add_option("--png", a->png, "Write a picture: hillshade, path and altitude profile");
  plan->callback([a] { runPlan(*a); });
}

}  // namespace skyroute::cli
