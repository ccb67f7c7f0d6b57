// skyroute gcs: subscribes as a ground station would (late joiners get every vehicle's current
// trajectory), prints trajectories and statuses as they arrive, and exports the latest trajectory
// of each vehicle to CSV, GeoJSON, KML and QGroundControl plans when it stops (--count reached,
// --timeout, or Ctrl-C). With --serve it also serves a live map page (gcs_live_map.hpp).
#include <algorithm>
#include <chrono>
#include <iostream>
#include <map>
#include <optional>

#include <CLI/CLI.hpp>

#include "service/cli/dds_cli_common.hpp"
#include "service/cli/dds_commands.hpp"
#include "service/cli/gcs_live_map.hpp"
#include "service/cli/nofly_option.hpp"
#include "service/cli/progress.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/qgc_plan.hpp"
#include "service/status_transitions.hpp"
#include "service/number_text.hpp"
#include "service/trajectory_export.hpp"

namespace skyroute::cli {

namespace {

struct GcsOptions {
  int domain = 0;
  std::string vehicle;
  int count = 0;         // stop after this many trajectories (0 = no limit)
  double timeout_s = 0;  // stop after this long (0 = until Ctrl-C)
  std::string csv, geojson, kml;
  std::string plan_dir;  // one QGroundControl .plan per vehicle
  std::string nofly;     // GeoJSON no-fly zones for the plans' geofence ("" = none)
  std::string serve;     // HOST:PORT of the live map ("" = none)
  std::string dem;       // the live map's terrain ("" = the embedded terrain)
  GcsWebLimits web;      // the live map's bounds (--allow-host, --serve-streams, --serve-timeout)
  bool progress = false; // show the waiting on stderr even when it is not a terminal
};

constexpr double kProgressEveryS = 5.0;  // how often a terminal hears that gcs is still waiting

void runGcs(const GcsOptions& o) {
  const std::string tool = "gcs";
  if (!o.nofly.empty() && o.plan_dir.empty() && o.serve.empty()) {
    fail(tool, kExitUsage, "--nofly applies to the --plan exports and the --serve map only");
  }
  // The zones in force: the file's (read before waiting, so a bad file fails at once), then those
  // published on the domain, by id.
  std::map<std::string, NoFlyZoneData> zones;
  if (!o.nofly.empty()) {
    for (NoFlyZoneData& zone : loadNoFlyZoneData(tool, "--nofly", o.nofly)) zones[zone.zone_id] = std::move(zone);
  }
  std::unique_ptr<GcsLiveMap> live = o.serve.empty() ? nullptr : GcsLiveMap::start(tool, o.serve, o.dem, o.web);
  dds::Entity participant = openParticipant(tool, o.domain);
  auto trajectories = openReader<TrajectoryData>(tool, participant);
  auto statuses = openReader<PlanStatusData>(tool, participant);
  auto loop = openWaitLoop(tool, participant);
  stopOnSignals(loop.waitsetHandle());
  if (live) live->announce();

  std::map<std::string, TrajectoryData> latest;  // per vehicle
  StatusTransitions printed_statuses;
  int received = 0;
  auto on_bad = [](const Error& e) { std::cerr << "skyroute gcs: skipped a bad sample: " << e.describe() << std::endl; };
  Status added = loop.add<TrajectoryData>(
      trajectories,
      [&](TrajectoryData&& t) {
        if (!o.vehicle.empty() && t.vehicle_id != o.vehicle) return;
        std::cout << describe(t) << std::endl;
        if (live) live->state().onTrajectory(t);
        latest[t.vehicle_id] = std::move(t);
        ++received;
        if (o.count > 0 && received >= o.count) loop.stop();
      },
      on_bad);
  if (!added) fail(tool, kExitServiceUnavailable, added.error().describe());
  added = loop.add<PlanStatusData>(
      statuses,
      [&](PlanStatusData&& s) {
        if (!o.vehicle.empty() && s.vehicle_id != o.vehicle) return;
        if (!printed_statuses.firstTime(s)) return;
        std::cout << describe(s) << std::endl;
        if (live) live->state().onStatus(s);
      },
      on_bad);
  if (!added) fail(tool, kExitServiceUnavailable, added.error().describe());
  for (const auto& [id, zone] : zones)
    if (live) live->state().onNoFlyZone(zone);
  auto zone_reader = openReader<NoFlyZoneData>(tool, participant);
  added = loop.add<NoFlyZoneData>(
      zone_reader,
      [&](NoFlyZoneData&& zone) {
        if (live) live->state().onNoFlyZone(zone);
        if (zone.remove) {
          zones.erase(zone.zone_id);
        } else {
          zones[zone.zone_id] = std::move(zone);
        }
      },
      on_bad);
  if (!added) fail(tool, kExitServiceUnavailable, added.error().describe());
  std::optional<dds::Reader<ObstacleUpdateData>> obstacles;  // only the map shows them
  if (live) {
    obstacles.emplace(openReader<ObstacleUpdateData>(tool, participant));
    added = loop.add<ObstacleUpdateData>(*obstacles, [&](ObstacleUpdateData&& u) { live->state().onObstacle(u); }, on_bad);
    if (!added) fail(tool, kExitServiceUnavailable, added.error().describe());
  }

  // Waits in slices, so a terminal shows that it is waiting and for what.
  const TerminalProgress progress(o.progress);
  const auto started = std::chrono::steady_clock::now();
  for (;;) {
    const double waited_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    double slice_s = kProgressEveryS;
    if (o.timeout_s > 0) slice_s = std::min(slice_s, o.timeout_s - waited_s);
    if (slice_s <= 0.0) break;
    auto outcome = loop.runOnce(slice_s);
    if (!outcome) fail(tool, kExitServiceUnavailable, outcome.error().describe());
    if (*outcome == dds::WaitLoop::Outcome::kStopped) break;
    const double now_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (o.timeout_s > 0 && now_s >= o.timeout_s) break;
    progress.step("waiting on domain " + std::to_string(o.domain) + ": " + std::to_string(latest.size()) +
                  " vehicle(s), " + std::to_string(received) + " trajectories so far" +
                  (o.timeout_s > 0 ? ", " + numberText(o.timeout_s - now_s, 3) + " s left" : " (Ctrl-C ends)"));
  }
  // An export with no trajectory in it would look like a result; nothing arrived is a timeout.
  // Serving the live map without exports, the page was the result, whatever it showed.
  const bool exports_asked = !o.csv.empty() || !o.geojson.empty() || !o.kml.empty() || !o.plan_dir.empty();
  if (latest.empty() && (exports_asked || !live)) {
    fail(tool, kExitServiceUnavailable,
         "no trajectory arrived on domain " + std::to_string(o.domain) +
             (o.vehicle.empty() ? "" : " for vehicle " + o.vehicle) +
             (o.timeout_s > 0 ? " within " + numberText(o.timeout_s) + " s" : "") + "; nothing written");
  }

  std::vector<TrajectoryData> current;
  for (auto& [vehicle, t] : latest) current.push_back(t);
  const std::pair<const std::string*, const char*> exports[] = {{&o.geojson, "GeoJSON"}, {&o.kml, "KML"}};
  if (!o.csv.empty()) {
    Status s = writeTrajectoriesCsv(o.csv, current);
    if (!s) fail(tool, kExitUsage, "--csv: " + s.error().describe());
    std::cout << "wrote " << current.size() << " trajectories to " << o.csv << std::endl;
  }
  for (const auto& [path, driver] : exports) {
    if (path->empty()) continue;
    Status s = writeTrajectoriesOgr(*path, driver, current);
    if (!s) fail(tool, kExitUsage, std::string("--") + (driver[0] == 'K' ? "kml" : "geojson") + ": " + s.error().describe());
    std::cout << "wrote " << current.size() << " trajectories to " << *path << std::endl;
  }
  if (!o.plan_dir.empty()) {
    std::vector<GeofencePolygon> geofence;
    for (const auto& [id, zone] : zones) geofence.push_back(geofencePolygon(zone));
    auto written = writeQgcPlanPerVehicle(o.plan_dir, current, geofence);
    if (!written) fail(tool, kExitUsage, "--plan: " + written.error().describe());
    for (const auto& path : *written) std::cout << "wrote " << path << std::endl;
  }
  if (o.count > 0 && received < o.count)
    fail(tool, kExitPlanningFailed,
         "received " + std::to_string(received) + " of " + std::to_string(o.count) + " trajectories on domain " +
             std::to_string(o.domain) + (o.timeout_s > 0 ? " within " + std::to_string(o.timeout_s) + " s" : ""));
}

}  // namespace

void addGcsCommand(CLI::App& app) {
  auto options = std::make_shared<GcsOptions>();
  CLI::App* cmd = app.add_subcommand("gcs", "Ground-station view: print trajectories and statuses, export them");
  cmd->add_option("--domain", options->domain, "DDS domain id")->capture_default_str();
  addSecurityOption(*cmd);
  cmd->add_option("--vehicle", options->vehicle, "Only this vehicle (default: every vehicle)");
  cmd->add_option("--count", options->count, "Stop after K trajectories (0 = no limit)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--timeout", options->timeout_s,
                  "Stop after S seconds (0 = until Ctrl-C); no trajectory by then exits 4 and writes nothing "
                  "(with --serve and no export: exits 0)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--csv", options->csv, "Write the latest trajectory of each vehicle as CSV (default: none)");
  cmd->add_option("--geojson", options->geojson,
                  "Write them as GeoJSON (3D lines, WGS84, heights above the ellipsoid; default: none)");
  cmd->add_option("--kml", options->kml, "Write them as KML (heights AMSL; default: none)");
  cmd->add_option("--plan", options->plan_dir, "Write one QGroundControl .plan per vehicle into this folder (default: none)");
  cmd->add_option("--nofly", options->nofly,
                  "GeoJSON no-fly zones (docs/nofly.md) for the --serve map and each --plan's exclusion geofence, "
                  "beside the zones published on the domain");
  cmd->add_flag("--progress", options->progress,
                "Say every 5 s on stderr what has arrived while waiting, even when stderr is not a terminal")
      ->capture_default_str();
  CLI::Option* serve = cmd->add_option("--serve", options->serve,
                  "Serve a live map page (terrain, trajectories, obstacles, altitude profile) on HOST:PORT, e.g. "
                  "127.0.0.1:8080 (port 0: a free port, printed at start). A malformed or foreign address exits 2, "
                  "a port in use exits 4")
      ->type_name("HOST:PORT");
  cmd->add_option("--dem", options->dem, "The live map's terrain: the DEM skyrouted plans on (default: the embedded terrain)");
  cmd->add_option("--allow-host", options->web.allowed_hosts,
                  "A host name (or address) the --serve map answers to besides localhost, 127.0.0.1, [::1] and "
                  "the --serve address; repeatable. Requests naming any other host are refused (421)")
      ->type_name("NAME")
      ->needs(serve);
  cmd->add_option("--serve-streams", options->web.max_event_streams,
                  "Open pages the --serve map follows live at once (event streams); more are told to retry (503)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str()
      ->needs(serve);
  cmd->add_option("--serve-timeout", options->web.request_timeout_s,
                  "Seconds a client of the --serve map has to send its whole request (408 after)")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str()
      ->needs(serve);
  cmd->footer("Example: skyroute gcs --domain 77 --timeout 60 --csv out/fleet.csv --kml out/fleet.kml\n" +
              std::string(kExitCodeTable));
  cmd->callback([options] { runGcs(*options); });
}

}  // namespace skyroute::cli
