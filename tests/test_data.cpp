#include "tests/test_data.hpp"

#include <filesystem>

#include <cpl_conv.h>
#include <ogr_srs_api.h>

#include "terrain/terrain_world.hpp"

namespace skyroute::testing {

std::string sharedDataPath(const std::string& relative) {
  const std::string path = std::string(SKYROUTE_SHARED_DATA_DIR) + "/" + relative;
  return std::filesystem::exists(path) ? path : std::string();
}

std::string projectDataPath(const std::string& relative) {
  return std::string(SKYROUTE_DATA_DIR) + "/" + relative;
}

std::string epsgWkt(int epsg) {
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  OSRImportFromEPSG(srs, epsg);
  char* wkt = nullptr;
  OSRExportToWkt(srs, &wkt);
  std::string out = wkt ? wkt : "";
  CPLFree(wkt);
  OSRDestroySpatialReference(srs);
  return out;
}

std::shared_ptr<const Heightfield> defaultTerrainHeightfield() {
  CollisionWorldOptions options;
  options.build_octree = false;
  auto loaded = loadTerrainWorld(projectDataPath("default_terrain.tif"), options);
  return loaded.ok() ? loaded->heightfield : nullptr;
}

}  // namespace skyroute::testing
