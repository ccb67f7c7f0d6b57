#include "tests/terrain_data.hpp"

#include <cpl_conv.h>
#include <ogr_srs_api.h>

#include "terrain/terrain_world.hpp"
#include "tests/test_data.hpp"

namespace skyroute::testing {

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
