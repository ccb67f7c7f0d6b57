// skyroute fleet: several vehicles, many tasks.
// - On a DEM (--dem, config terrain.dem, or the embedded terrain), points in latitude, longitude
//   and altitude: the 3D fleet mission skyrouted plans (MissionPipeline::planFleet: GMTPA on the
//   flight band, every route through the trajectory stage, separation certified and repaired by
//   start delays), with skyrouted's configuration. Writes the trajectories as `skyroute gcs` does.
// - --domain N: the same request to a running skyrouted over DDS (fleet_dds_command.cpp).
// - --map F.map, or --cells with a DEM: the 2D grid problem on cells (fleet_grid.hpp).
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "service/cli/commands.hpp"
#include "service/cli/nofly_option.hpp"
#include "service/cli/dds_commands.hpp"
#include "service/cli/fleet_common.hpp"
#include "service/cli/fleet_grid.hpp"
#include "service/daemon_config.hpp"
#include "service/map_figure.hpp"
#include "service/trajectory_figure.hpp"
#include "service/mission_pipeline.hpp"

namespace skyroute::cli {

namespace {

const std::string kTool = "fleet";

struct FleetCommandArgs {
  std::optional<std::string> nofly;
  ConfigArgs config;
  std::optional<std::string> dem;
  std::string map;
  bool cells = false;
  FleetInputArgs input;           // --file, --vehicles, --tasks, --ends, --request-id, the limits
  std::optional<int> domain;
  double wait_s = 120.0;
  double budget_s = 60.0;
  std::string out;
  std::string png;
  FleetGridArgs grid;             // the grid's own options (--algo, --seed, --capacity, --cell-size-m)
  // Options that belong to one way of running only, to refuse them in the others.
  std::vector<CLI::Option*> grid_only, geo_only, dds_only, local_only;
};

void refuse(const std::vector<CLI::Option*>& options, const std::string& why) {
  for (const CLI::Option* option : options) {
    if (option->count() > 0) fail(kTool, kExitUsage, option->get_name() + " " + why);
  }
}

// The trajectories over the terrain, one colour per vehicle (as in its KML): each vehicle's begin
// as a depot square and each task as a ring in the colour of the vehicle that flies over it.
void writePng(const std::string& path, const WorldModel& world, const FleetRequestData& request,
              const FleetPlanOutput& plan) {
  MapFigureContent figure;
  figure.title = "skyroute fleet: " + std::to_string(plan.trajectories.size()) + " vehicles, " +
                 std::to_string(request.tasks.size()) + " tasks";
  for (std::size_t i = 0; i < plan.trajectories.size(); ++i) {
    const std::string& id = plan.trajectories[i].vehicle_id;
    figure.lines.push_back(trajectoryLine(plan.trajectories[i], id.empty() ? "vehicle " + std::to_string(i + 1) : id,
                                          vehicleRgb(i)));
  }
  for (std::size_t i = 0; i < plan.begins_m.size(); ++i) {
    figure.markers.push_back({MarkerKind::kDepot, plan.begins_m[i].head<2>(), 0, vehicleRgb(i)});
  }
  for (std::size_t i = 0; i < plan.status.allocation.size(); ++i) {
    for (std::uint32_t task : plan.status.allocation[i].tasks) {
      if (task >= plan.tasks_m.size()) continue;
      figure.markers.push_back({MarkerKind::kTask, plan.tasks_m[task].head<2>(), 0, vehicleRgb(i)});
    }
  }
  if (Status saved = saveTerrainFigure(world.terrain(), figure, path); !saved.ok()) {
    fail(kTool, kExitUsage, "--png " + saved.error().describe());
  }
}

void runGeoFleet(const FleetCommandArgs& a) {
  DaemonConfig config = loadConfig(kTool, a.config);
  if (a.dem) config.dem_path = *a.dem;
  const PipelineOptions& p = config.engine.pipeline;
  if (auto bad = validatePipelineOptions(p)) fail(kTool, kExitUsage, bad->describe());
  if (printConfigIfAsked(a.config, config)) return;
  if (!(a.budget_s > 0.0)) fail(kTool, kExitUsage, "--budget-s: must be > 0");
  checkOutputPath(kTool, "--out", a.out, fleetTrajectoryFormats());
  checkOutputPath(kTool, "--png", a.png, {"png"});
  const FleetRequestData request = buildFleetRequest(kTool, a.input, "fleet");
  checkFleetRequest(kTool, a.input, request, p.fleet);

  const std::string dem = demPathOf(kTool, config);
  std::cerr << "loading " << dem << " ..." << std::endl;
  auto world = WorldModel::load(dem, config.world);
  if (!world.ok()) fail(kTool, kExitBadInput, (a.dem ? "--dem " : "terrain.dem ") + world.error().describe());
  loadNoFlyZones(kTool, a.nofly, config, **world, static_cast<double>(utcNowNs()) * 1e-9);
  const MissionPipeline pipeline(*world, p);
  std::cerr << "planning " << request.vehicle_ids.size() << " vehicles and " << request.tasks.size() << " tasks ..."
            << std::endl;
  const FleetPlanOutput plan =
      pipeline.planFleet(request, utcNowNs(), TerminationCondition::afterMilliseconds(a.budget_s * 1e3));
  if (!plan.ok()) {
    const FleetStatusData& s = plan.status;
    const int code = isFleetInputError(s.error_code) ? fleetInputExitCode(a.input, s.field) : kExitPlanningFailed;
    // The status message is "field: reason"; the field is said as the user wrote it.
    const std::string reason = !s.field.empty() && s.message.rfind(s.field + ": ", 0) == 0
                                   ? s.message.substr(s.field.size() + 2)
                                   : s.message;
    const std::string where = fleetUserField(a.input, s.field);
    fail(kTool, code, (where.empty() ? "" : where + ": ") + reason + " [" + std::string(to_string(s.error_code)) + "]");
  }
  printFleetOutcome(request, plan.status, plan.trajectories);
  if (!a.out.empty()) writeFleetTrajectories(kTool, a.out, plan.trajectories);
  if (!a.png.empty()) {
    writePng(a.png, **world, request, plan);
    std::printf("wrote %s\n", a.png.c_str());
  }
}

void runFleetDds(const FleetCommandArgs& a) {
  refuse(a.grid_only, "applies to grid cells only (--map, or --cells)");
  refuse(a.local_only, "applies to planning here, not with --domain (the service has its own)");
  if (!a.config.path.empty() || a.config.print) {
    fail(kTool, kExitUsage, "--config applies to planning here, not with --domain (the service has its own)");
  }
  checkOutputPath(kTool, "--out", a.out, fleetTrajectoryFormats());
  const FleetRequestData request =
      buildFleetRequest(kTool, a.input, "fleet-" + std::to_string(::getpid()) + "-" + std::to_string(utcNowNs() / 1000000));
  checkFleetRequest(kTool, a.input, request);
  requestFleetOverDds(kTool, request, *a.domain, a.wait_s, a.out);
}

void runFleetGrid(FleetCommandArgs& a) {
  refuse(a.geo_only, "applies to latitude/longitude fleets only, not to grid cells");
  refuse(a.dds_only, "applies to latitude/longitude fleets only, not to grid cells");
  FleetGridArgs& g = a.grid;
  g.map = a.map;
  if (g.map.empty()) g.dem = a.dem ? *a.dem : demPathOf(kTool, loadConfig(kTool, a.config));
  g.vehicles = a.input.vehicles;
  g.tasks = a.input.tasks;
  g.budget_s = a.budget_s;
  g.out = a.out;
  g.png = a.png;
  if (a.input.limits.clearance_m) g.grid_options.min_clearance_m = *a.input.limits.clearance_m;
  if (a.input.limits.ceiling_m) g.grid_options.flight_ceiling_m = *a.input.limits.ceiling_m;
  runFleetOnGrid(g);
}

void runFleet(FleetCommandArgs& a) {
  if (!a.map.empty() && a.dem) fail(kTool, kExitUsage, "give --map FILE.map or --dem FILE, not both");
  if (a.domain) {
    runFleetDds(a);
  } else if (!a.map.empty() || a.cells) {
    runFleetGrid(a);
  } else {
    refuse(a.grid_only, "applies to grid cells only (--map, or --cells)");
    refuse(a.dds_only, "applies with --domain only");
    runGeoFleet(a);
  }
}

void addInputOptions(CLI::App& cmd, FleetCommandArgs& a) {
  a.geo_only.push_back(cmd.add_option("--file", a.input.file,
                                      "Fleet JSON: request_id, vehicle_ids, begins, tasks, ends, limits, planner "
                                      "(docs/dds.md)"));
  cmd.add_option("--vehicles", a.input.vehicles,
                 "Vehicles \"ID@LAT,LON,ALT;...\" (or \"LAT,LON,ALT;...\": uav-1 .. uav-N) where each begins; "
                 "cells: depots \"X,Y;...\"");
  cmd.add_option("--tasks", a.input.tasks, "Tasks \"LAT,LON,ALT;...\" (overflown); cells: \"X,Y;...\"");
  a.geo_only.push_back(
      cmd.add_option("--ends", a.input.ends, "Where each vehicle ends \"LAT,LON,ALT;...\" (default: its begin)"));
  a.geo_only.push_back(cmd.add_option("--request-id", a.input.request_id,
                                      "Request id (default: the file's; else fleet here, fleet-PID-MS over DDS)"));
  addFlightBandOptions(
      cmd, a.input.limits,
      "; cells on a DEM: the grid's band (default " + numberText(TerrainGridOptions{}.min_clearance_m) +
          " m clearance, ceiling " + numberText(TerrainGridOptions{}.flight_ceiling_m) + " m)");
  for (CLI::Option* option : addVehicleDynamicsOptions(cmd, a.input.limits)) a.geo_only.push_back(option);
  // The grid's names before --clearance-m and --ceiling-m, kept for one release (hidden).
  cmd.add_option("--clearance", a.input.limits.clearance_m, "old name of --clearance-m")->group("");
  cmd.add_option("--ceiling", a.input.limits.ceiling_m, "old name of --ceiling-m")->group("");
}

void addModeOptions(CLI::App& cmd, FleetCommandArgs& a) {
  a.local_only.push_back(cmd.add_option("--dem", a.dem, "DEM file (config terrain.dem; default: the embedded terrain)"));
  CLI::Option* nofly = addNoFlyOption(cmd, a.nofly);
  a.local_only.push_back(nofly);
  a.geo_only.push_back(nofly);
  a.local_only.push_back(cmd.add_option("--map", a.map, "Moving AI .map file: the 2D problem on cells (x column, y row)"));
  a.local_only.push_back(
      cmd.add_flag("--cells", a.cells, "The 2D problem on the DEM's flight-band grid, points as X,Y cells (x east, y north)"));
  a.dds_only.push_back(
      cmd.add_option("--domain", a.domain, "Send the request to a running skyrouted on this DDS domain instead"));
  a.dds_only.push_back(addSecurityOption(cmd));
  a.dds_only.push_back(cmd.add_option("--wait", a.wait_s, "--domain: seconds to wait for the service and its answer")
                           ->check(CLI::PositiveNumber)
                           ->capture_default_str());
  a.local_only.push_back(cmd.add_option("--budget-s", a.budget_s, "Time limit of the planning here, seconds")
                             ->capture_default_str());
  cmd.add_option("--out", a.out,
                 "Write the trajectories: .csv (the columns of skyroute gcs --csv), .geojson or .kml; cells: the "
                 "plan as .json");
  a.local_only.push_back(cmd.add_option("--png", a.png, "Draw the routes, one colour per vehicle (on the hillshade)"));
}

void addGridOptions(CLI::App& cmd, FleetCommandArgs& a) {
  a.grid_only.push_back(
      cmd.add_option("--algo", a.grid.algo, "Cells: allocation greedy (GMTPA Algorithm 1), ga (genetic baseline), exact")
          ->check(CLI::IsMember({"greedy", "ga", "exact"}))
          ->capture_default_str());
  a.grid_only.push_back(
      cmd.add_option("--seed", a.grid.seed, "Cells: random seed of the genetic algorithm")->capture_default_str());
  a.grid_only.push_back(
      cmd.add_option("--capacity", a.grid.capacity, "Cells: most tasks per vehicle (0: no limit)")->capture_default_str());
  a.grid_only.push_back(cmd.add_option("--cell-size-m", a.grid.grid_options.cell_size_m,
                                       "Cells on a DEM: grid cell edge, metres")
                            ->capture_default_str());
  a.grid_only.push_back(
      cmd.add_option("--cell-size", a.grid.grid_options.cell_size_m, "old name of --cell-size-m")->group(""));
}

}  // namespace

void addFleetCommand(CLI::App& app) {
  auto a = std::make_shared<FleetCommandArgs>();
  CLI::App* cmd = app.add_subcommand(
      "fleet", "Several vehicles, many tasks: GMTPA allocation and separated 3D trajectories, as skyrouted plans them");
  cmd->footer(helpFooter(
      {"skyroute fleet --file data/missions/demo_fleet.json --out out/fleet.kml --png out/fleet.png",
       "skyroute fleet --vehicles 'a@46.90,15.03,900;b@46.90,15.15,900' --tasks '46.95,15.06,1000;46.97,15.12,1000'",
       "skyroute fleet --domain 0 --file data/missions/demo_fleet.json",
       "skyroute fleet --map room.map --vehicles '1,1;2,0' --tasks '4,1;4,3;2,3' --algo exact --out plan.json"}));
  addConfigOptions(*cmd, a->config);
  addModeOptions(*cmd, *a);
  addInputOptions(*cmd, *a);
  addGridOptions(*cmd, *a);
  cmd->callback([a] { runFleet(*a); });
}

}  // namespace skyroute::cli
