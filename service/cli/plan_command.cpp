// skyroute plan: one mission through the mission pipeline (the daemon's own), written out as the
// daemon would publish it. The mission comes from a mission file (the JSON `skyroute request
// --file` publishes) or from --from/--via/--to; the configuration from --config (skyrouted's keys).
#include <cstdio>
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
#include "service/cli/mission_args.hpp"
#include "service/cli/nofly_option.hpp"
#include "service/daemon_config.hpp"
#include "service/map_figure.hpp"
#include "service/mission_json.hpp"
#include "service/mission_pipeline.hpp"
#include "service/qgc_plan.hpp"
#include "service/trajectory_export.hpp"
#include "service/trajectory_figure.hpp"

namespace skyroute::cli {
namespace {

const std::string kTool = "plan";

struct PlanArgs {
  ConfigArgs config;
  std::optional<std::string> dem;
  std::optional<std::string> nofly;
  MissionPointArgs mission;  // --mission, --from/--via/--to, --fixed-order and the vehicle limits
  std::string vehicle;
  std::string planner;
  std::optional<std::uint64_t> seed;
  std::optional<std::uint64_t> iterations;
  std::optional<double> budget_s;
  std::optional<double> dt_s;
  std::optional<std::string> mission_point_mode;
  std::string out;
  std::string png;
  HeightRefArgs height_ref;
};

MissionRequestData buildMission(const PlanArgs& a) {
  MissionRequestData m = buildMissionRequest(kTool, a.mission);
  if (!a.vehicle.empty()) m.vehicle_id = a.vehicle;
  if (m.vehicle_id.empty()) m.vehicle_id = "uav-1";
  if (m.request_id.empty()) m.request_id = m.vehicle_id + "-plan";
  if (!a.planner.empty()) m.planner = a.planner;
  return m;
}

// The trajectory over the terrain under it, cropped to the route, with the planner's legs, the
// mission points in visiting order and the altitude profile below.
void writePng(const std::string& path, const WorldModel& world, const MissionPlan& plan, const TrajectoryData& data) {
  const Heightfield& terrain = world.terrain();
  MapFigureContent figure;
  char title[160];
  std::snprintf(title, sizeof title, "%s  \u00B7  %s  \u00B7  seed %llu  \u00B7  %.0f s", data.vehicle_id.c_str(),
                std::string(plan.mission.planner->name).c_str(), static_cast<unsigned long long>(plan.seed),
                data.samples.empty() ? 0.0 : data.samples.back().t_rel_s);
  figure.title = title;
  for (const RouteLeg& leg : plan.flight->route().legs) {
    figure.lines.push_back({"planned legs", groundTrack(leg.rrt.path_m), Rgb{250, 220, 60}, 1.5, true});
  }
  figure.lines.push_back(trajectoryLine(data, "trajectory", Rgb{220, 20, 20}));
  const std::vector<Eigen::Vector3d>& points = plan.mission.ordered_m;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const MarkerKind kind = i == 0 ? MarkerKind::kStart
                            : i + 1 == points.size() ? MarkerKind::kEnd
                                                     : MarkerKind::kMissionPoint;
    figure.markers.push_back({kind, points[i].head<2>(), static_cast<int>(i), Rgb{30, 60, 200}});
  }
  figure.profile = trajectoryProfile(terrain, data);
  figure.profile->clearance_m = plan.mission.world->options().min_clearance_m;
  if (Status saved = saveTerrainFigure(terrain, figure, path); !saved.ok()) {
    fail(kTool, kExitUsage, "--png " + saved.error().describe());
  }
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
  if (plan.mission.limits.fixedWing()) {
    const FeasibilityReport& c = report.final_check;
    std::printf("fixed wing: speed %.1f..%.1f m/s (minimum airspeed %.1f), bank up to %.1f deg (limit %.1f), load "
                "factor up to %.2f (limit %.2f), climb up to %.1f deg, descent up to %.1f deg\n",
                c.min_speed_mps, c.max_speed_mps, plan.mission.limits.minAirspeedMps(), c.max_bank_deg,
                plan.mission.limits.max_bank_deg, c.max_load_factor, plan.mission.limits.maxLoadFactor(),
                c.max_climb_angle_deg, c.max_descent_angle_deg);
  }
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
  if (a.mission_point_mode) {
    p.replan.route.trajectory.fixed_waypoint_mode = parseFixedWaypointMode(*a.mission_point_mode).value();
  }
  if (auto bad = validatePipelineOptions(p)) fail(kTool, kExitUsage, bad->describe());
  if (printConfigIfAsked(a.config, config)) return;
  checkOutputPath(kTool, "--out", a.out, {"csv", "geojson", "json", "plan", "waypoints"});
  checkOutputPath(kTool, "--png", a.png, {"png"});
  const MissionRequestData mission = missionInAmsl(kTool, a.height_ref, a.mission.mission_file, buildMission(a));

  const std::string dem = demPathOf(kTool, config);
  std::cerr << "loading " << dem << " ..." << std::endl;
  auto world = WorldModel::load(dem, config.world);
  if (!world.ok()) fail(kTool, kExitBadInput, "terrain.dem " + world.error().describe());
  const double now_s = static_cast<double>(utcNowNs()) * 1e-9;
  loadNoFlyZones(kTool, a.nofly, config, **world, now_s);
  // The daemon's audit, in the same pipeline: a trajectory that fails it fails the plan, and
  // nothing is written.
  p.audit_counters = std::make_shared<AuditCounters>();
  const MissionPipeline pipeline(*world, p);
  auto progress = [](PlanStage, const std::string& what) { std::cerr << what << " ..." << std::endl; };
  auto planned = pipeline.plan(PipelineRequest{mission, std::nullopt, std::nullopt}, now_s, {}, progress);
  if (!planned.ok()) failPlanError(kTool, a.mission, planned.error());
  std::printf("audit: passed (%llu trajectory audited: samples every %g s against the DEM, the ceiling, %zu no-fly "
              "zones and the vehicle's limits)\n",
              static_cast<unsigned long long>(p.audit_counters->audits.load()), p.audit.step_s,
              (*world)->noFlyZones().size());
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
      auto qgc = qgcMissionFromTrajectory(data, geofencePolygons((*world)->noFlyZones(), (*world)->frame()));
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
  plan->footer(helpFooter({"skyroute plan --mission data/missions/demo_mission.json --out out/plan.csv",
                           "skyroute plan --from 46.90,15.03,1100 --via 46.95,15.06,1150 --to 46.97,15.12,1100 "
                           "--png out/plan.png"}));
  addConfigOptions(*plan, a->config);
  plan->add_option("--dem", a->dem, "DEM file (config terrain.dem; default: the embedded terrain)");
  addNoFlyOption(*plan, a->nofly);
  plan->add_option("--mission", a->mission.mission_file,
                   "Mission JSON, as `skyroute request --file` publishes it (docs/dds.md); options below override it");
  plan->add_option("--from", a->mission.from, "Start LAT,LON,ALT (degrees, degrees, metres AMSL)");
  plan->add_option("--to", a->mission.to, "Goal LAT,LON,ALT");
  plan->add_option("--via", a->mission.via,
                   "Mission points LAT,LON,ALT (repeatable, or ';'-separated); MMD*L orders them unless --fixed-order")
      ->delimiter(';');
  plan->add_flag("--fixed-order", a->mission.fixed_order, "Visit the points in the given order");
  addHeightRefOption(*plan, a->height_ref);
  plan->add_option("--vehicle", a->vehicle, "Vehicle id (default: the mission's, else uav-1)");
  plan->add_option("--planner", a->planner,
                   "Route planner: " + routePlannerNames(" | ") + " (default: config planning.default_planner)");
  plan->add_option("--seed", a->seed, "Seed of the plan (config planning.seed)")
      ->default_str(std::to_string(PipelineOptions{}.seed));
  plan->add_option("--iterations", a->iterations, "Search iterations per leg (config planning.leg_max_iterations)")
      ->default_str(std::to_string(PlanBudget{}.leg_max_iterations));
  plan->add_option("--budget-s", a->budget_s,
                   "Wall-clock cap per leg, seconds; 0 = none (config planning.leg_time_cap_s)")
      ->check(CLI::Range(0.0, 3600.0))
      ->default_str(numberText(PlanBudget{}.leg_time_cap_s));
  plan->add_option("--dt", a->dt_s, "Sample spacing of the output, seconds (config planning.sample_dt_s)")
      ->check(CLI::Range(0.001, 10.0))
      ->default_str(numberText(PipelineOptions{}.sample_dt_s));
  plan->add_option("--mission-point-mode", a->mission_point_mode,
                   "At each mission point: pass = fly through, slowed for the corner, stopping only where that "
                   "cannot fly (the summary notes each such point); stop = come to rest at every point "
                   "(config planning.mission_point_mode)")
      ->check(CLI::IsMember({"pass", "stop"}))
      ->default_str("pass");
  addFlightBandOptions(*plan, a->mission.limits);
  addVehicleDynamicsOptions(*plan, a->mission.limits);
  plan->add_option("--out", a->out,
                   "Write the trajectory: .csv (the columns of skyroute gcs --csv), .geojson, .json, or a "
                   "QGroundControl .plan / .waypoints");
  plan->add_option("--png", a->png, "Write a picture: hillshade, path and altitude profile");
  plan->callback([a] { runPlan(*a); });
}

}  // namespace skyroute::cli
