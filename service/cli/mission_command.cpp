// skyroute mission: the visiting order of a mission's points.
// - On a DEM (--dem, config terrain.dem, or the embedded terrain), points in latitude, longitude
//   and altitude: the mission pipeline's validate and order stages, as skyrouted runs them (MMD*L
//   on the flight band, or the straight-line fallback with its reason), with skyrouted's
//   configuration. Prints the order, the method, the cost matrix in metres and each leg's end
//   points; --out writes the legs (or the points) as CSV, GeoJSON or KML.
// - On a grid (--map F.map, or --cells with a DEM), points as X,Y cells: mission_grid.hpp.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "service/cli/cli_common.hpp"
#include "service/cli/nofly_option.hpp"
#include "service/cli/commands.hpp"
#include "service/cli/mission_args.hpp"
#include "service/daemon_config.hpp"
#include "service/cli/mission_grid.hpp"
#include "service/mission_order_export.hpp"
#include "service/mission_pipeline.hpp"

namespace skyroute::cli {
namespace {

const std::string kTool = "mission";

// The output formats of --out, one OGR driver each.
const std::vector<std::pair<std::string, std::string>> kOutFormats = {
    {"csv", "CSV"}, {"geojson", "GeoJSON"}, {"kml", "KML"}};

struct MissionCommandArgs {
  std::optional<std::string> nofly;
  ConfigArgs config;
  std::optional<std::string> dem;
  std::string map;
  bool cells = false;
  MissionPointArgs points;        // --mission, --from/--via/--to, --fixed-order, the flight band
  bool json = false;
  std::string out;
  std::string out_geometry = "legs";
  MissionGridArgs grid;           // the grid's own options (--algo, --paper-moves, --paths, --cell-size-m)
  std::vector<CLI::Option*> grid_only;   // options that mean nothing on a DEM's lat/lon mission
  std::vector<CLI::Option*> geo_only;    // and those that mean nothing on a grid
};

std::string pointName(int index, int count) {
  if (index == 0) return "begin";
  if (index == count - 1) return "end";
  return "points[" + std::to_string(index - 1) + "]";
}

std::string methodText(const MissionRequestData& mission, const MissionOrder& order) {
  if (order.method == "mmdstar") {
    char text[96];
    std::snprintf(text, sizeof text, "mmdstar (MMD*L on a %.1f m flight-band grid)", order.cell_size_m);
    return text;
  }
  if (order.method == "euclidean") return "euclidean fallback: " + order.fallback_reason;
  return mission.fixed_order ? "fixed (the mission fixes the order)" : "fixed (one point or none: nothing to order)";
}

// The request's points in visiting order, with their WGS84 positions as the user gave them.
std::vector<OrderedPoint> visitedPoints(const MissionRequestData& mission, const OrderedMission& ordered,
                                        const LocalFrame& frame) {
  std::vector<const MissionPointData*> given{&mission.begin};
  for (const MissionPointData& p : mission.points) given.push_back(&p);
  given.push_back(&mission.end);
  const int count = static_cast<int>(given.size());
  std::vector<OrderedPoint> visited;
  for (int index : ordered.order) {
    const MissionPointData& p = *given[static_cast<std::size_t>(index)];
    const Eigen::Vector3d& enu = ordered.points_m[static_cast<std::size_t>(index)];
    visited.push_back(OrderedPoint{index, pointName(index, count),
                                   p.frame == MissionPointData::Frame::kWgs84 ? p.geo : frame.toGeo(enu), enu});
  }
  return visited;
}

// Each leg's cost by the order's metric: the matrix's entry, or the straight line for a fixed order.
std::vector<double> legCosts(const MissionOrder& order, const std::vector<OrderedPoint>& visited) {
  std::vector<double> costs;
  for (std::size_t k = 0; k + 1 < visited.size(); ++k) {
    const OrderedPoint& a = visited[k];
    const OrderedPoint& b = visited[k + 1];
    costs.push_back(order.cost_matrix_m.empty() ? (b.enu_m - a.enu_m).norm()
                                                : order.cost_matrix_m[static_cast<std::size_t>(a.point)]
                                                                     [static_cast<std::size_t>(b.point)]);
  }
  return costs;
}

nlohmann::json geoJson(const GeoPoint& g) {
  return {{"lat_deg", g.lat_deg}, {"lon_deg", g.lon_deg}, {"alt_amsl_m", g.alt_amsl_m}};
}

nlohmann::json orderJson(const std::string& dem, const MissionRequestData& mission, const OrderedMission& ordered,
                         const std::vector<OrderedPoint>& visited, const std::vector<double>& costs) {
  const MissionOrder& o = ordered.ordering;
  nlohmann::json j;
  j["terrain"] = dem;
  j["method"] = o.method;
  j["method_text"] = methodText(mission, o);
  j["fallback_reason"] = o.fallback_reason;
  j["order"] = ordered.order;
  for (const OrderedPoint& p : visited) j["order_labels"].push_back(p.label);
  j["cost_m"] = o.cost_m;
  j["cell_size_m"] = o.cell_size_m;
  j["expansions"] = o.expansions;
  j["time_ms"] = o.time_ms;
  j["cost_matrix_m"] = nlohmann::json::array();
  for (const auto& row : o.cost_matrix_m) {
    nlohmann::json r = nlohmann::json::array();
    for (double v : row) r.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr));
    j["cost_matrix_m"].push_back(r);
  }
  j["legs"] = nlohmann::json::array();
  for (std::size_t k = 0; k + 1 < visited.size(); ++k) {
    const OrderedPoint& a = visited[k];
    const OrderedPoint& b = visited[k + 1];
    j["legs"].push_back({{"from_point", a.point}, {"to_point", b.point}, {"from_label", a.label},
                         {"to_label", b.label}, {"from", geoJson(a.geo)}, {"to", geoJson(b.geo)},
                         {"cost_m", costs[k]}, {"straight_m", (b.enu_m - a.enu_m).norm()}});
  }
  return j;
}

void printOrder(const nlohmann::json& j, const std::vector<OrderedPoint>& visited) {
  std::string labels, indices;
  for (const OrderedPoint& p : visited) {
    labels += (labels.empty() ? "" : " -> ") + p.label;
    indices += (indices.empty() ? "" : ",") + std::to_string(p.point);
  }
  std::printf("terrain     %s\n", j["terrain"].get<std::string>().c_str());
  std::printf("order       %s  (%s)\n", labels.c_str(), indices.c_str());
  std::printf("method      %s\n", j["method_text"].get<std::string>().c_str());
  std::printf("cost        %.1f m\n", j["cost_m"].get<double>());
  std::printf("expansions  %llu\n", j["expansions"].get<unsigned long long>());
  std::printf("time        %.3f ms\n", j["time_ms"].get<double>());
  const auto& matrix = j["cost_matrix_m"];
  if (matrix.empty()) {
    std::printf("cost matrix none (a fixed order compares no costs)\n");
  } else {
    const int count = static_cast<int>(matrix.size());
    std::printf("cost matrix, m (row: from, column: to; '-' not planned)\n%11s", "");
    for (int c = 0; c < count; ++c) std::printf("%11s", pointName(c, count).c_str());
    std::printf("\n");
    for (int r = 0; r < count; ++r) {
      std::printf("%11s", pointName(r, count).c_str());
      for (const auto& v : matrix[static_cast<std::size_t>(r)]) {
        if (v.is_null()) {
          std::printf("%11s", "-");
        } else {
          std::printf("%11.1f", v.get<double>());
        }
      }
      std::printf("\n");
    }
  }
  for (std::size_t k = 0; k < j["legs"].size(); ++k) {
    const auto& leg = j["legs"][k];
    auto where = [](const nlohmann::json& g) {
      char text[96];
      std::snprintf(text, sizeof text, "%.6f,%.6f,%.1f", g["lat_deg"].get<double>(), g["lon_deg"].get<double>(),
                    g["alt_amsl_m"].get<double>());
      return std::string(text);
    };
    std::printf("leg %zu      %s %s -> %s %s: cost %.1f m, straight %.1f m\n", k,
                leg["from_label"].get<std::string>().c_str(), where(leg["from"]).c_str(),
                leg["to_label"].get<std::string>().c_str(), where(leg["to"]).c_str(), leg["cost_m"].get<double>(),
                leg["straight_m"].get<double>());
  }
}

void runGeoMission(const MissionCommandArgs& a) {
  for (const CLI::Option* option : a.grid_only) {
    if (option->count() > 0) fail(kTool, kExitUsage, option->get_name() + " applies to grid cells only (--map, or --cells)");
  }
  DaemonConfig config = loadConfig(kTool, a.config);
  if (a.dem) config.dem_path = *a.dem;
  const PipelineOptions& p = config.engine.pipeline;
  if (auto bad = validatePipelineOptions(p)) fail(kTool, kExitUsage, bad->describe());
  if (printConfigIfAsked(a.config, config)) return;
  std::vector<std::string> extensions;
  for (const auto& [ext, driver] : kOutFormats) extensions.push_back(ext);
  checkOutputPath(kTool, "--out", a.out, extensions);
  const auto geometry = parseOrderGeometry(a.out_geometry);
  MissionRequestData mission = buildMissionRequest(kTool, a.points);
  if (mission.vehicle_id.empty()) mission.vehicle_id = "uav-1";
  if (mission.request_id.empty()) mission.request_id = mission.vehicle_id + "-mission";

  const std::string dem = demPathOf(kTool, config);
  std::cerr << "loading " << dem << " ..." << std::endl;
  auto world = WorldModel::load(dem, config.world);
  if (!world.ok()) fail(kTool, kExitBadInput, (a.dem ? "--dem " : "terrain.dem ") + world.error().describe());
  const double now_s = static_cast<double>(utcNowNs()) * 1e-9;
  loadNoFlyZones(kTool, a.nofly, config, **world, now_s);
  const MissionPipeline pipeline(*world, p);
  auto ordered = pipeline.order(mission, now_s);
  if (!ordered.ok()) failPlanError(kTool, a.points, ordered.error());
  const std::vector<OrderedPoint> visited = visitedPoints(mission, *ordered, (*world)->frame());
  const std::vector<double> costs = legCosts(ordered->ordering, visited);
  const nlohmann::json j = orderJson(dem, mission, *ordered, visited, costs);
  if (a.json) {
    std::cout << j.dump() << std::endl;
  } else {
    printOrder(j, visited);
  }
  if (a.out.empty()) return;
  const std::string ext = lowerExtension(a.out);
  for (const auto& [known, driver] : kOutFormats) {
    if (known != ext) continue;
    Status written = writeMissionOrder(a.out, driver, visited, costs, *geometry);
    if (!written.ok()) fail(kTool, kExitUsage, "--out " + written.error().describe());
  }
  std::cerr << "wrote the " << a.out_geometry << " to " << a.out << std::endl;
}

void runMission(MissionCommandArgs& a) {
  if (!a.map.empty() && a.dem) fail(kTool, kExitUsage, "give --map FILE.map or --dem FILE, not both");
  if (a.map.empty() && !a.cells) {
    runGeoMission(a);
    return;
  }
  for (const CLI::Option* option : a.geo_only) {
    if (option->count() > 0) fail(kTool, kExitUsage, option->get_name() + " applies to latitude/longitude missions only, not to grid cells");
  }
  MissionGridArgs& g = a.grid;
  g.map = a.map;
  if (g.map.empty()) g.dem = a.dem ? *a.dem : demPathOf(kTool, loadConfig(kTool, a.config));
  g.from = a.points.from;
  g.via = a.points.via;
  g.to = a.points.to;
  g.json = a.json;
  if (a.points.limits.clearance_m) g.grid_options.min_clearance_m = *a.points.limits.clearance_m;
  if (a.points.limits.ceiling_m) g.grid_options.flight_ceiling_m = *a.points.limits.ceiling_m;
  runMissionOnGrid(g);
}

}  // namespace

void addMissionCommand(CLI::App& app) {
  auto a = std::make_shared<MissionCommandArgs>();
  CLI::App* cmd = app.add_subcommand(
      "mission", "Visiting order of a mission's points: MMD*L cost matrix and open TSP, as skyrouted orders them");
  cmd->footer(helpFooter(
      {"skyroute mission --from 46.90,15.03,1100 --via '46.95,15.06,1150;46.92,15.10,1100' --to 46.97,15.12,1100",
       "skyroute mission --mission data/missions/demo_mission.json --json --out out/order.kml",
       "skyroute mission --map room.map --from 1,1 --via '20,3;7,28' --to 30,30 --algo dstar-lite"}));
  addConfigOptions(*cmd, a->config);
  cmd->add_option("--dem", a->dem, "DEM file (config terrain.dem; default: the embedded terrain)");
  cmd->add_option("--map", a->map, "Moving AI .map file: points are X,Y cells");
  a->geo_only.push_back(addNoFlyOption(*cmd, a->nofly));
  cmd->add_flag("--cells", a->cells, "Points are X,Y cells of the DEM's flight-band grid (always so with --map)");
  a->geo_only.push_back(cmd->add_option("--mission", a->points.mission_file,
                                        "Mission JSON, as `skyroute request --file` publishes it (docs/dds.md); "
                                        "the options below override it"));
  cmd->add_option("--from", a->points.from, "Begin LAT,LON,ALT (degrees, degrees, metres AMSL); X,Y with cells");
  cmd->add_option("--to", a->points.to, "End LAT,LON,ALT; X,Y with cells");
  cmd->add_option("--via", a->points.via, "Mission points between them, ';'-separated or repeated; X,Y with cells")
      ->delimiter(';');
  // The names before --from/--via/--to, kept for one release (hidden).
  cmd->add_option("--begin", a->points.from, "old name of --from")->group("");
  cmd->add_option("--points", a->points.via, "old name of --via")->group("")->delimiter(';');
  cmd->add_option("--end", a->points.to, "old name of --to")->group("");
  a->geo_only.push_back(cmd->add_flag("--fixed-order", a->points.fixed_order, "Visit the points in the given order"));
  addFlightBandOptions(*cmd, a->points.limits,
                       "; with --cells on a DEM, the grid's band (default " +
                           numberText(TerrainGridOptions{}.min_clearance_m) + " m clearance, ceiling " +
                           numberText(TerrainGridOptions{}.flight_ceiling_m) + " m)");
  // The vehicle's limits belong to the request the order stage validates (a value out of range
  // is refused, named as given); the grid takes the flight band only.
  for (CLI::Option* option : addVehicleDynamicsOptions(*cmd, a->points.limits)) a->geo_only.push_back(option);
  cmd->add_flag("--json", a->json, "Print one JSON object instead of text");
  a->geo_only.push_back(cmd->add_option("--out", a->out, "Write the ordered mission: .csv, .geojson or .kml (docs/exports.md)"));
  a->geo_only.push_back(cmd->add_option("--out-geometry", a->out_geometry, "What --out holds: legs (straight 3D lines) or points")
                            ->check(CLI::IsMember({"legs", "points"}))
                            ->capture_default_str());
  a->grid_only.push_back(cmd->add_option("--algo", a->grid.algo, "Cells: mmdstar (MMD*L) or dstar-lite (one D* Lite per pair)")
                             ->check(CLI::IsMember({"mmdstar", "dstar-lite"}))
                             ->capture_default_str());
  a->grid_only.push_back(
      cmd->add_flag("--paper-moves", a->grid.paper_moves, "Cells: diagonal cost 1.4 and the Chebyshev heuristic (the paper's)"));
  a->grid_only.push_back(cmd->add_flag("--paths", a->grid.with_paths, "Cells: include every leg's cells in the JSON"));
  a->grid_only.push_back(cmd->add_option("--cell-size-m", a->grid.grid_options.cell_size_m,
                                         "Cells on a DEM: grid cell edge, metres")
                             ->capture_default_str());
  cmd->callback([a] { runMission(*a); });
}

}  // namespace skyroute::cli
