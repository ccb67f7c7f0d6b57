// skyroute terrain info | generate
#include <cstdio>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <cpl_string.h>
#include <gdal.h>
#include <nlohmann/json.hpp>
#include <ogr_srs_api.h>

#include "service/cli/commands.hpp"
#include "service/map_image.hpp"
#include "terrain/terrain_generator.hpp"
#include "terrain/terrain_world.hpp"

namespace skyroute::cli {
namespace {

struct InfoArgs {
  std::string dem;
  bool json = false;
  std::string png;
  double octree_resolution_m = 90.0;
};

void runInfo(const InfoArgs& args) {
  CollisionWorldOptions options;
  options.octree_resolution_m = args.octree_resolution_m;
  options.ceiling_m = 1.0e9;
  if (!args.json) std::cerr << "loading " << args.dem << " ..." << std::endl;
  auto world = loadTerrainWorld(args.dem, options);
  if (!world.ok()) {
    std::cerr << "skyroute terrain info: " << world.error().describe() << " [" << to_string(world.error().code)
              << "]\n";
    throw CLI::RuntimeError(2);
  }
  const Dem& dem = *world->dem;
  const Heightfield& hf = *world->heightfield;
  const TerrainOctree* octree = world->collision->octree();
  const auto& bounds = hf.boundsEn();
  const GeoPoint anchor = hf.frame().anchor();
  nlohmann::json j;
  j["file"] = args.dem;
  j["crs"] = dem.crsName();
  j["geographic"] = dem.isGeographic();
  j["width"] = dem.width();
  j["height"] = dem.height();
  j["resolution_m"] = {dem.resolutionM().x(), dem.resolutionM().y()};
  j["min_height_m"] = dem.minHeightM();
  j["max_height_m"] = dem.maxHeightM();
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
  j["build_seconds"] = {{"load", world->load_seconds},
                        {"heightfield", world->heightfield_seconds},
                        {"octree", octree->stats().build_seconds},
                        {"collision_ready", world->load_seconds + world->heightfield_seconds + world->collision_seconds}};
  if (!args.png.empty()) {
    auto image = MapImage::hillshade(dem);
    Status saved = image.ok() ? image->savePng(args.png) : Status(image.error());
    if (!saved.ok()) {
      std::cerr << "skyroute terrain info: --png " << saved.error().describe() << "\n";
      throw CLI::RuntimeError(2);
    }
    j["png"] = args.png;
  }
  if (args.json) {
    std::cout << j.dump() << std::endl;
    return;
  }
  std::printf("file          %s\n", args.dem.c_str());
  std::printf("crs           %s%s\n", dem.crsName().c_str(), dem.isGeographic() ? " (geographic)" : " (projected)");
  std::printf("size          %d x %d cells, %.1f x %.1f m per cell\n", dem.width(), dem.height(), dem.resolutionM().x(),
              dem.resolutionM().y());
  std::printf("extent        %.1f x %.1f km (ENU, anchored at %.5f, %.5f)\n", bounds.sizes().x() / 1000.0,
              bounds.sizes().y() / 1000.0, anchor.lat_deg, anchor.lon_deg);
  std::printf("heights       %.1f .. %.1f m\n", dem.minHeightM(), dem.maxHeightM());
  std::printf("voids         %d cells filled, %d cells unknown\n", dem.filledVoidCells(), dem.unknownCells());
  std::printf("octree        %.0f m: %zu nodes, %zu leaves\n", args.octree_resolution_m, octree->stats().node_count,
              octree->stats().leaf_count);
  std::printf("memory        dem %.1f MiB, heightfield %.1f MiB, octree %.1f MiB\n", dem.memoryBytes() / 1048576.0,
              hf.memoryBytes() / 1048576.0, octree->stats().memory_bytes / 1048576.0);
  std::printf("build         load %.3f s, heightfield %.3f s, octree %.3f s; collision checks ready after %.3f s\n",
              world->load_seconds, world->heightfield_seconds, octree->stats().build_seconds,
              world->load_seconds + world->heightfield_seconds + world->collision_seconds);
  if (!args.png.empty()) std::printf("hillshade     %s\n", args.png.c_str());
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

  auto info_args = std::make_shared<InfoArgs>();
  CLI::App* info = terrain->add_subcommand("info", "Summary of a DEM: CRS, size, heights, voids, memory, build times");
  info->add_option("dem", info_args->dem, "DEM file (any raster GDAL opens)")->required();
  info->add_flag("--json", info_args->json, "Print one JSON object");
  info->add_option("--png", info_args->png, "Write a hillshade PNG to this file");
  info->add_option("--octree-res", info_args->octree_resolution_m, "Octree resolution in metres")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  info->callback([info_args] { runInfo(*info_args); });

  auto gen_args = std::make_shared<GenerateArgs>();
  CLI::App* gen = terrain->add_subcommand("generate", "Write the seeded synthetic mountain DEM (the embedded default terrain)");
  gen->add_option("--out", gen_args->out, "Output GeoTIFF")->required();
  gen->add_option("--seed", gen_args->options.seed, "Random seed")->capture_default_str();
  gen->add_option("--width", gen_args->options.width, "Cells east-west")->check(CLI::Range(16, 4096))->capture_default_str();
  gen->add_option("--height", gen_args->options.height, "Cells north-south")->check(CLI::Range(16, 4096))->capture_default_str();
  gen->add_option("--cell", gen_args->options.cell_size_m, "Cell size in metres")->check(CLI::Range(1.0, 1000.0))->capture_default_str();
  gen->callback([gen_args] { runGenerate(*gen_args); });
}

}  // namespace skyroute::cli
