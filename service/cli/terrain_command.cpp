// skyroute terrain info | height | generate
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>
#include <cpl_string.h>
#include <gdal.h>
#include <nlohmann/json.hpp>
#include <ogr_srs_api.h>

#include "service/cli/cli_common.hpp"
#include "service/cli/commands.hpp"
#include "service/cli/progress.hpp"
#include "service/map_image.hpp"
#include "service/memory_guard.hpp"
#include "service/mission_point_check.hpp"
#include "service/number_text.hpp"
#include "terrain/terrain_generator.hpp"
#include "terrain/terrain_world.hpp"

namespace skyroute::cli {
namespace {

struct InfoArgs {
  std::string dem;
  bool json = false;
  std::string png;
  double octree_resolution_m = 90.0;
  bool progress = false;
  double max_memory_mb = 0.0;  // 0 = half the machine's free memory
};

// Refuses an octree the machine cannot hold before it is built, and shows the steps of a load.
TerrainLoadObserver guardedLoad(const InfoArgs& args, const TerminalProgress& progress) {
  return [&args, &progress](const std::string& step, const TerrainWorld& so_far) -> Status {
    if (step == "heightfield") {
      progress.step("read " + args.dem + " in " + numberText(so_far.load_seconds, 3) + " s; building the heightfield");
      return Status::success();
    }
    const std::size_t estimate = estimateOctreePeakBytes(*so_far.heightfield, args.octree_resolution_m);
    std::size_t limit = static_cast<std::size_t>(args.max_memory_mb * 1024.0 * 1024.0);
    std::string source = "--max-memory-mb";
    if (args.max_memory_mb <= 0.0) {
      const auto available = availableMemoryBytes();
      if (!available) return Status::success();  // no /proc/meminfo: nothing to judge by
      limit = *available / 2;
      source = "half of MemAvailable " + bytesText(*available) + "; --max-memory-mb sets another limit";
    }
    const std::string what = "the octree at " + numberText(args.octree_resolution_m) + " m";
    if (Status fits = checkMemoryEstimate(estimate, limit, source, "--octree-res", what); !fits.ok()) return fits;
    progress.step("building " + what + " (about " + bytesText(estimate) + ")");
    return Status::success();
  };
}

nlohmann::json infoJson(const InfoArgs& args, const TerrainWorld& world) {
  const Dem& dem = *world.dem;
  const Heightfield& hf = *world.heightfield;
  const TerrainOctree* octree = world.collision->octree();
  const auto& bounds = hf.boundsEn();
  const GeoPoint anchor = hf.frame().anchor();
  const GeoBoundsDeg geo = terrainGeoBounds(hf);
  nlohmann::json j;
  j["file"] = args.dem;
  j["crs"] = dem.crsName();
  j["geographic"] = dem.isGeographic();
  j["width"] = dem.width();
  j["height"] = dem.height();
  j["resolution_m"] = {dem.resolutionM().x(), dem.resolutionM().y()};
  j["min_height_m"] = dem.minHeightM();
  j["max_height_m"] = dem.maxHeightM();
  j["bounds_wgs84"] = {{"south_deg", geo.south_deg}, {"north_deg", geo.north_deg},
                       {"west_deg", geo.west_deg}, {"east_deg", geo.east_deg}};
  j["heights_amsl_m"] = {{"min", dem.minHeightM()}, {"max", dem.maxHeightM()}};
  j["voids"] = {{"filled_cells", dem.filledVoidCells()}, {"unknown_cells", dem.unknownCells()}};
  j["frame_anchor"] = {{"lat_deg", anchor.lat_deg}, {"lon_deg", anchor.lon_deg}, {"alt_amsl_m", anchor.alt_amsl_m}};
  j["extent_enu_m"] = {{"east_min", bounds.min().x()}, {"east_max", bounds.max().x()},
                       {"north_min", bounds.min().y()}, {"north_max", bounds.max().y()}};
  j["octree"] = {{"resolution_m", args.octree_resolution_m},
                 {"nodes", octree->stats().node_count},
                 {"leaves", octree->stats().leaf_count},
                 {"memory_bytes", octree->stats().memory_bytes}};
  j["memory_bytes"] = {{"dem", dem.memoryBytes()}, {"heightfield", hf.memoryBytes()},
                       {"octree", octree->stats().memory_bytes}};
  j["build_seconds"] = {{"load", world.load_seconds},
                        {"heightfield", world.heightfield_seconds},
                        {"octree", octree->stats().build_seconds},
                        {"collision_ready", world.load_seconds + world.heightfield_seconds + world.collision_seconds}};
  return j;
}

void printInfoText(const InfoArgs& args, const TerrainWorld& world) {
  const Dem& dem = *world.dem;
  const Heightfield& hf = *world.heightfield;
  const TerrainOctree* octree = world.collision->octree();
  const auto& bounds = hf.boundsEn();
  const GeoPoint anchor = hf.frame().anchor();
  std::printf("file          %s\n", args.dem.c_str());
  std::printf("crs           %s%s\n", dem.crsName().c_str(), dem.isGeographic() ? " (geographic)" : " (projected)");
  std::printf("size          %d x %d cells, %.1f x %.1f m per cell\n", dem.width(), dem.height(), dem.resolutionM().x(),
              dem.resolutionM().y());
  std::printf("wgs84 bounds  %s\n", describe(terrainGeoBounds(hf)).c_str());
  std::printf("extent        %.1f x %.1f km (ENU, anchored at %.5f, %.5f)\n", bounds.sizes().x() / 1000.0,
              bounds.sizes().y() / 1000.0, anchor.lat_deg, anchor.lon_deg);
  std::printf("heights       %.1f .. %.1f m AMSL\n", dem.minHeightM(), dem.maxHeightM());
  std::printf("voids         %d cells filled, %d cells unknown\n", dem.filledVoidCells(), dem.unknownCells());
  std::printf("octree        %.0f m: %zu nodes, %zu leaves\n", args.octree_resolution_m, octree->stats().node_count,
              octree->stats().leaf_count);
  std::printf("memory        dem %.1f MiB, heightfield %.1f MiB, octree %.1f MiB\n", dem.memoryBytes() / 1048576.0,
              hf.memoryBytes() / 1048576.0, octree->stats().memory_bytes / 1048576.0);
  std::printf("build         load %.3f s, heightfield %.3f s, octree %.3f s; collision checks ready after %.3f s\n",
              world.load_seconds, world.heightfield_seconds, octree->stats().build_seconds,
              world.load_seconds + world.heightfield_seconds + world.collision_seconds);
  if (!args.png.empty()) std::printf("hillshade     %s\n", args.png.c_str());
}

void runInfo(const InfoArgs& args) {
  CollisionWorldOptions options;
  options.octree_resolution_m = args.octree_resolution_m;
  options.ceiling_m = 1.0e9;
  const TerminalProgress progress(args.progress);
  progress.step("loading " + args.dem);
  auto world = loadTerrainWorld(args.dem, options, {}, guardedLoad(args, progress));
  if (!world.ok()) {
    const int code = world.error().field == "--octree-res" ? kExitUsage : kExitBadInput;
    fail("terrain info", code, world.error().describe() + " [" + std::string(to_string(world.error().code)) + "]");
  }
  nlohmann::json j = infoJson(args, *world);
  if (!args.png.empty()) {
    auto image = MapImage::hillshade(*world->dem);
    Status saved = image.ok() ? image->savePng(args.png) : Status(image.error());
    if (!saved.ok()) fail("terrain info", kExitUsage, "--png " + saved.error().describe());
    j["png"] = args.png;
  }
  if (args.json) {
    std::cout << j.dump() << std::endl;
    return;
  }
  printInfoText(args, *world);
}

struct HeightArgs {
  std::string dem;
  std::vector<std::string> points;  // "LAT,LON" as written
  bool json = false;
};

// "LAT,LON" -> (lat, lon); nullopt when the text is not two finite numbers.
std::optional<std::pair<double, double>> parseLatLon(const std::string& text) {
  std::istringstream in(text);
  double v[2];
  char comma = 0;
  std::string rest;
  if (!(in >> v[0] >> comma >> v[1]) || comma != ',' || (in >> rest) || !std::isfinite(v[0]) || !std::isfinite(v[1])) {
    return std::nullopt;
  }
  return std::pair{v[0], v[1]};
}

// Every point gets its line, in the order given: its height, or why it has none. A point
// without a height does not hide the others' (one void point used to end the command with no
// height printed at all); the exit code then says some failed.
void runHeight(const HeightArgs& args) {
  auto dem = Dem::load(args.dem);
  if (!dem.ok()) fail("terrain height", kExitBadInput, "--dem " + dem.error().describe());
  auto terrain = Heightfield::build(*dem);
  if (!terrain.ok()) fail("terrain height", kExitBadInput, "--dem " + terrain.error().describe());
  nlohmann::json rows = nlohmann::json::array();
  std::vector<std::string> lines;
  std::size_t failed = 0;
  for (const std::string& text : args.points) {
    nlohmann::json row{{"point", text}};
    std::optional<std::string> reason;
    const auto lat_lon = parseLatLon(text);
    if (!lat_lon) {
      reason = "not LAT,LON (two numbers in degrees)";
    } else {
      const auto [lat_deg, lon_deg] = *lat_lon;
      row["lat_deg"] = lat_deg;
      row["lon_deg"] = lon_deg;
      if (std::abs(lat_deg) > 90.0) {
        reason = "latitude " + numberText(lat_deg) +
                 " is outside [-90, 90]: latitude and longitude may be swapped (write LAT,LON)";
      } else if (auto off = offTerrainReason(**terrain, MissionPointData::wgs84(lat_deg, lon_deg, 0.0))) {
        reason = "the point " + *off;
      }
    }
    if (reason) {
      ++failed;
      row["ground_amsl_m"] = nullptr;
      row["error"] = *reason;
      lines.push_back(text + " no height: " + *reason);
    } else {
      const double ground_m = *groundHeightAmslM(**terrain, lat_lon->first, lat_lon->second);
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.1f", ground_m);
      lines.push_back(text + " " + buf + " m AMSL");
      row["ground_amsl_m"] = ground_m;
    }
    rows.push_back(std::move(row));
  }
  if (args.json) {
    std::cout << rows.dump() << std::endl;
  } else {
    for (const std::string& line : lines) std::cout << line << "\n";
    std::cout << std::flush;
  }
  if (failed > 0) {
    fail("terrain height", kExitUsage,
         std::to_string(failed) + " of " + std::to_string(args.points.size()) +
             (args.points.size() == 1 ? " point has" : " points have") + " no height (each says why)");
  }
}

struct GenerateArgs {
  TerrainGeneratorOptions options;
  std::string out;
};

void runGenerate(const GenerateArgs& args) {
  const auto& o = args.options;
  const std::vector<float> heights = generateTerrainHeights(o);
  GDALDriverH gtiff = GDALGetDriverByName("GTiff");
  CPLStringList create_options;
  create_options.AddNameValue("COMPRESS", "DEFLATE");
  create_options.AddNameValue("PREDICTOR", "2");
  create_options.AddNameValue("ZLEVEL", "9");
  GDALDatasetH ds = GDALCreate(gtiff, args.out.c_str(), o.width, o.height, 1, GDT_Int16, create_options.List());
  if (!ds) {
    std::cerr << "skyroute terrain generate: --out " << args.out << ": cannot create (" << CPLGetLastErrorMsg() << ")\n";
    throw CLI::RuntimeError(2);
  }
  double gt[6] = {o.origin_easting_m, o.cell_size_m, 0.0, o.origin_northing_m, 0.0, -o.cell_size_m};
  GDALSetGeoTransform(ds, gt);
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  OSRImportFromEPSG(srs, o.epsg);
  char* wkt = nullptr;
  OSRExportToWkt(srs, &wkt);
  GDALSetProjection(ds, wkt);
  CPLFree(wkt);
  OSRDestroySpatialReference(srs);
  std::vector<std::int16_t> ints(heights.size());
  for (std::size_t i = 0; i < heights.size(); ++i) ints[i] = static_cast<std::int16_t>(std::lround(heights[i]));
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  GDALSetRasterUnitType(band, "m");
  const CPLErr err = GDALRasterIO(band, GF_Write, 0, 0, o.width, o.height, ints.data(), o.width, o.height, GDT_Int16, 0, 0);
  GDALSetMetadataItem(ds, "SKYROUTE_GENERATOR",
                      ("skyroute terrain generate --seed " + std::to_string(o.seed)).c_str(), nullptr);
  GDALClose(ds);
  if (err != CE_None) {
    std::cerr << "skyroute terrain generate: --out " << args.out << ": write failed\n";
    throw CLI::RuntimeError(2);
  }
  std::printf("wrote %s: %d x %d cells of %.0f m, EPSG:%d, seed %u\n", args.out.c_str(), o.width, o.height,
              o.cell_size_m, o.epsg, o.seed);
}

}  // namespace

void addTerrainCommands(CLI::App& app) {
  CLI::App* terrain = app.add_subcommand("terrain", "Inspect or generate terrain (DEM) files");
  terrain->require_subcommand(1);
  terrain->footer("Example: skyroute terrain info data/default_terrain.tif\n" + std::string(kExitCodeTable));

  auto info_args = std::make_shared<InfoArgs>();
  CLI::App* info = terrain->add_subcommand(
      "info", "Summary of a DEM: CRS, size, WGS84 bounds, heights AMSL, voids, memory, build times");
  info->add_option("dem", info_args->dem, "DEM file (any raster GDAL opens)")->required();
  info->add_flag("--json", info_args->json, "Print one JSON object")->capture_default_str();
  info->add_option("--png", info_args->png, "Write a hillshade PNG to this file (default: none)");
  info->add_option("--octree-res", info_args->octree_resolution_m, "Octree resolution in metres")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  info->add_option("--max-memory-mb", info_args->max_memory_mb,
                   "Refuse an octree whose estimated build memory exceeds this (0 = half the machine's free memory)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  info->add_flag("--progress", info_args->progress, "Show the loading steps on stderr even when it is not a terminal")
      ->capture_default_str();
  info->footer("Example: skyroute terrain info data/default_terrain.tif --json --png hillshade.png\n" +
               std::string(kExitCodeTable));
  info->callback([info_args] { runInfo(*info_args); });

  auto height_args = std::make_shared<HeightArgs>();
  CLI::App* height = terrain->add_subcommand("height", "Ground height AMSL at each point (LAT,LON in degrees)");
  height->add_option("--dem", height_args->dem, "DEM file (any raster GDAL opens)")->required();
  height->add_option("points", height_args->points, "Points as LAT,LON (degrees, WGS84)")->required();
  height->add_flag("--json", height_args->json, "Print one JSON array")->capture_default_str();
  height->footer("Example: skyroute terrain height --dem data/default_terrain.tif 46.93,15.1 46.96,15.12\n"
                 "Each point gets a line, its height or why it has none (outside the DEM, a DEM void, not LAT,LON); "
                 "exit 2 when any point has none.\n" +
                 std::string(kExitCodeTable));
  height->callback([height_args] { runHeight(*height_args); });

  auto gen_args = std::make_shared<GenerateArgs>();
  CLI::App* gen = terrain->add_subcommand("generate", "Write the seeded synthetic mountain DEM (the embedded default terrain)");
  gen->add_option("--out", gen_args->out, "Output GeoTIFF")->required();
  gen->add_option("--seed", gen_args->options.seed, "Random seed")->capture_default_str();
  gen->add_option("--width", gen_args->options.width, "Cells east-west")->check(CLI::Range(16, 4096))->capture_default_str();
  gen->add_option("--height", gen_args->options.height, "Cells north-south")->check(CLI::Range(16, 4096))->capture_default_str();
  gen->add_option("--cell", gen_args->options.cell_size_m, "Cell size in metres")->check(CLI::Range(1.0, 1000.0))->capture_default_str();
  gen->footer("Example: skyroute terrain generate --out my_terrain.tif --seed 7\n" + std::string(kExitCodeTable));
  gen->callback([gen_args] { runGenerate(*gen_args); });
}

}  // namespace skyroute::cli
