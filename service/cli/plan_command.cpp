// skyroute plan: a route through given points, in the given order, as a sampled trajectory.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "service/cli/commands.hpp"
#include "service/geo_samples.hpp"
#include "service/grid_leg_planner.hpp"
#include "service/map_image.hpp"
#include "service/route_planner.hpp"
#include "service/trajectory_data.hpp"
#include "service/trajectory_export.hpp"
#include "terrain/terrain_world.hpp"

namespace skyroute::cli {
namespace {

struct PlanArgs {
  std::string dem = SKYROUTE_DEFAULT_DEM;
  std::string from;
  std::string to;
  std::vector<std::string> via;
  double clearance_m = 50.0;
  double ceiling_m = 5000.0;
  double vref_mps = 50.0;
  std::uint64_t seed = 1;
  double budget_ms = 200.0;
  std::uint64_t iterations = 0;
  double dt_s = 0.5;
  std::string out;
  std::string png;
  std::string planner = "rrtstar_lospo";
};

[[noreturn]] void fail(const std::string& field, const std::string& message, int code = 2) {
  std::cerr << "skyroute plan: " << field << ": " << message << "\n";
  throw CLI::RuntimeError(code);
}

GeoPoint parseLatLonAlt(const std::string& text, const std::string& field) {
  std::vector<double> v;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(part, &used));
      if (used != part.size()) throw std::invalid_argument(part);
    } catch (const std::exception&) {
      fail(field, "'" + text + "' is not LAT,LON,ALT (degrees, degrees, metres AMSL)");
    }
  }
  if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
    fail(field, "'" + text + "' is not LAT,LON,ALT (degrees, degrees, metres AMSL)");
  }
  if (std::abs(v[0]) > 90.0 || std::abs(v[1]) > 180.0) fail(field, "latitude or longitude out of range in '" + text + "'");
  return GeoPoint{v[0], v[1], v[2]};
}

std::string lowerExtension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

void writePng(const PlanArgs& args, const TerrainWorld& world, const PlannedRoute& route,
              const std::vector<TrajectoryState>& samples) {
  auto image = MapImage::hillshade(*world.dem);
  if (!image.ok()) fail("--png", image.error().describe());
  std::vector<Eigen::Vector3d> flown;
  std::vector<double> altitude;
  std::vector<double> ground;
  for (const auto& s : samples) {
    flown.push_back(s.position_m);
    altitude.push_back(s.position_m.z());
    ground.push_back(world.heightfield->heightAt(s.position_m.x(), s.position_m.y()));
  }
  for (const RouteLeg& leg : route.legs) image->drawPathEn(*world.heightfield, leg.rrt.path_m, Rgb{250, 250, 120}, 1);
  image->drawPathEn(*world.heightfield, flown, Rgb{220, 20, 20}, 3);
  for (const RouteLeg& leg : route.legs) {
    image->drawDisc(world.heightfield->enToPixel(leg.path_m.front().x(), leg.path_m.front().y()), 5, Rgb{20, 20, 220});
    image->drawDisc(world.heightfield->enToPixel(leg.path_m.back().x(), leg.path_m.back().y()), 5, Rgb{20, 20, 220});
  }
  image->appendProfile(altitude, ground, std::max(120, image->height() / 4));
  Status saved = image->savePng(args.png);
  if (!saved.ok()) fail("--png", saved.error().describe());
}

void runPlan(const PlanArgs& args) {
  CollisionWorldOptions options;
  options.min_clearance_m = args.clearance_m;
  options.ceiling_m = args.ceiling_m;
  options.vehicle_radius_m = std::min(5.0, args.clearance_m);
  options.build_octree = false;  // every check here runs on the heightfield
  std::cerr << "loading " << args.dem << " ..." << std::endl;
  auto world = loadTerrainWorld(args.dem, options);
  if (!world.ok()) fail(world.error().field.empty() ? "--dem" : world.error().field, world.error().message);
  const LocalFrame& frame = world->heightfield->frame();

  std::vector<std::pair<std::string, GeoPoint>> named;
  named.emplace_back("--from", parseLatLonAlt(args.from, "--from"));
  for (std::size_t i = 0; i < args.via.size(); ++i) {
    named.emplace_back("--via[" + std::to_string(i) + "]", parseLatLonAlt(args.via[i], "--via"));
  }
  named.emplace_back("--to", parseLatLonAlt(args.to, "--to"));
  std::vector<Eigen::Vector3d> points;
  for (const auto& [name, geo] : named) {
    const Eigen::Vector3d p = frame.toEnu(geo);
    Status ok = checkRoutePoint(*world->collision, p, name);
    if (!ok.ok()) fail(name, ok.error().message);
    points.push_back(p);
  }

  RouteOptions route_options;
  route_options.seed = args.seed;
  route_options.leg_budget_ms = args.budget_ms;
  route_options.leg_max_iterations = args.iterations;
  VehicleLimits limits;
  limits.v_ref_mps = args.vref_mps;
  limits.max_speed_mps = std::max(limits.max_speed_mps, 1.2 * args.vref_mps);
  std::cerr << "planning " << points.size() - 1 << " leg(s) ..." << std::endl;
  Result<PlannedRoute> route = make_error(ErrorCode::kInternal, "planner", "not run");
  if (auto grid_planner = parseGridGlobalPlanner(args.planner)) {
    // HAB-PP on the flight band per leg, then the same trajectory stage.
    route = planGridRoutePaths(world->collision, points, *grid_planner, GridLegOptions{}, args.seed);
    if (route.ok()) {
      if (Status built = buildRouteTrajectory(world->collision, points, limits, route_options, *route); !built.ok())
        route = built.error();
    }
  } else {
    route = planRoute(world->collision, points, limits, route_options);
  }
  if (!route.ok()) {
    const Error& e = route.error();
    std::string field = e.field;
    // Map route point names back to the command line's.
    if (field.rfind("points[", 0) == 0) field = named[std::stoul(field.substr(7))].first;
    fail(field, e.message + " [" + std::string(to_string(e.code)) + "]", 3);
  }
  const Trajectory& trajectory = route->built.trajectory;
  const auto samples = trajectory.sample(args.dt_s);

  double rrt_length = 0.0;
  double lospo_length = 0.0;
  for (const RouteLeg& leg : route->legs) {
    rrt_length += leg.rrt.length_m;
    lospo_length += leg.lospo_length_m;
  }
  std::printf("route: %zu legs, %s %.0f m, after LOSPO %.0f m (%.1f%% shorter), %zu waypoints\n", route->legs.size(),
              args.planner.c_str(),
              rrt_length, lospo_length, 100.0 * (1.0 - lospo_length / rrt_length), route->waypoints_m.size());
  std::printf("trajectory: %.1f s, %s, max speed %.1f m/s, max accel %.2f m/s^2, planned in %.0f ms\n",
              trajectory.duration_s(), std::string(to_string(route->built.report.status)).c_str(),
              route->built.report.final_check.max_speed_mps, route->built.report.final_check.max_accel_mps2,
              route->planning_ms);
  for (const std::string& repair : route->built.report.repairs) std::printf("  repair: %s\n", repair.c_str());

  if (!args.out.empty()) {
    const std::string ext = lowerExtension(args.out);
    if (ext == "csv") {
      Status s = writeTrajectoryCsv(args.out, toGeoSamples(samples, frame));
      if (!s.ok()) fail("--out", s.error().describe());
    } else if (ext == "geojson" || ext == "json") {
      TrajectoryData data = toTrajectoryData(trajectory, frame, args.dt_s, utcNowNs(),
                                             TrajectoryIdentity{"cli", "plan-" + std::to_string(args.seed), 0, ""});
      for (const RouteLeg& leg : route->legs) {
        data.legs.push_back(LegBoundaryData{static_cast<std::uint32_t>(leg.from_point),
                                            static_cast<std::uint32_t>(leg.to_point), leg.start_s, leg.end_s});
      }
      if (ext == "geojson") {
        Status s = writeTrajectoriesOgr(args.out, "GeoJSON", {data});
        if (!s.ok()) fail("--out", s.error().describe());
      } else {
        nlohmann::json j;
        j["duration_s"] = trajectory.duration_s();
        j["length_m"] = lospo_length;
        j["status"] = to_string(route->built.report.status);
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
        std::ofstream out(args.out);
        if (!out) fail("--out", "cannot write " + args.out);
        out << j.dump(1) << "\n";
      }
    } else {
      fail("--out", "unknown format '." + ext + "' (use .csv, .geojson or .json)");
    }
    std::printf("wrote %zu samples to %s\n", samples.size(), args.out.c_str());
  }
  if (!args.png.empty()) {
    writePng(args, *world, *route, samples);
    std::printf("wrote %s\n", args.png.c_str());
  }
}

}  // namespace

void addPlanCommand(CLI::App& app) {
  auto args = std::make_shared<PlanArgs>();
  CLI::App* plan = app.add_subcommand("plan", "Plan a 3D route through points in the given order (RRT*, LOSPO, 7th-order splines)");
  plan->add_option("--dem", args->dem, "DEM file (default: the embedded terrain)")->capture_default_str();
  plan->add_option("--from", args->from, "Start LAT,LON,ALT (degrees, degrees, metres AMSL)")->required();
  plan->add_option("--to", args->to, "Goal LAT,LON,ALT")->required();
  plan->add_option("--via", args->via, "Intermediate LAT,LON,ALT, in order (repeatable)");
  plan->add_option("--clearance", args->clearance_m, "Minimum height above ground, m")->check(CLI::Range(1.0, 5000.0))->capture_default_str();
  plan->add_option("--ceiling", args->ceiling_m, "Highest altitude, m AMSL")->capture_default_str();
  plan->add_option("--vref", args->vref_mps, "Reference speed V_ref, m/s")->check(CLI::Range(0.5, 150.0))->capture_default_str();
  plan->add_option("--seed", args->seed, "Random seed")->capture_default_str();
  plan->add_option("--budget-ms", args->budget_ms, "RRT* time per leg, ms (0 = use --iterations only)")->check(CLI::Range(0.0, 600000.0))->capture_default_str();
  plan->add_option("--iterations", args->iterations, "RRT* iteration budget per leg (reproducible; 0 = none)")->capture_default_str();
  plan->add_option("--dt", args->dt_s, "Sampling step of the output, s")->check(CLI::Range(0.01, 60.0))->capture_default_str();
  plan->add_option("--out", args->out, "Write the sampled trajectory (.csv, .geojson or .json)");
  plan->add_option("--png", args->png, "Write a picture: hillshade, path and altitude profile");
  plan->add_option("--planner", args->planner, "Global planner of each leg: rrtstar_lospo, hab-pp or hab-pp-rrt")
      ->check(CLI::IsMember({"rrtstar_lospo", "hab-pp", "hab-pp-rrt"}))
      ->capture_default_str();
  plan->callback([args] {
    if (args->budget_ms <= 0.0 && args->iterations == 0) fail("--budget-ms", "needs a time budget or --iterations");
    runPlan(*args);
  });
}

}  // namespace skyroute::cli
