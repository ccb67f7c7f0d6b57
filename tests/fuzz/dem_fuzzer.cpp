// Fuzzes DEM loading (skyrouted's terrain.dem, `skyroute plan --dem`): raster bytes written to
// GDAL's /vsimem/ and loaded as the daemon loads its terrain (loadTerrainWorld without the octree,
// with a terrain margin),
// then asked what planning asks of it: heights, clearance along a segment, point and segment
// validity across the flyable box. The first byte picks the file name, hence the GDAL driver;
// only the drivers of real DEM formats stay registered (GDAL's own drivers are fuzzed by GDAL).
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <string>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal.h>

#include "terrain/terrain_world.hpp"

namespace {

// Each name selects a driver by extension or naming rule (SRTMHGT reads the tile from the name).
// Not "N44W072.hgt.zip": GDAL 3.6's SRTMHGT reads a corrupt zip through a null file handle (a
// segfault in gdal_translate as well; docs/fuzzing.md), which no caller can prevent.
constexpr std::array<const char*, 5> kNames = {"dem.tif", "dem.asc", "dem.dem", "N44W072.hgt", "dem.xyz"};
constexpr const char* kKeptDrivers[] = {"GTiff", "AAIGrid", "USGSDEM", "SRTMHGT", "XYZ"};
constexpr const char* kDir = "/vsimem/dem_fuzzer";

bool kept(const char* driver) {
  for (const char* k : kKeptDrivers)
    if (std::strcmp(driver, k) == 0) return true;
  return false;
}

// Checked after every input too: a later GDALAllRegister would bring every driver back.
void requireOnlyKeptDrivers() {
  if (GDALGetDriverCount() == static_cast<int>(std::size(kKeptDrivers))) return;
  std::fprintf(stderr, "dem_fuzzer: %d GDAL drivers registered, expected the %zu kept ones\n", GDALGetDriverCount(),
               std::size(kKeptDrivers));
  std::abort();
}

void writeFile(const std::string& path, const std::uint8_t* data, std::size_t size) {
  VSIFCloseL(VSIFileFromMemBuffer(path.c_str(), const_cast<GByte*>(data), size, /*bTakeOwnership=*/FALSE));
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  CPLSetConfigOption("GDAL_PAM_ENABLED", "NO");  // no .aux.xml side files
  CPLSetConfigOption("GDAL_DISABLE_READDIR_ON_OPEN", "EMPTY_DIR");
  CPLSetErrorHandler(CPLQuietErrorHandler);
  // Dem::load registers GDAL's drivers once, on the first file it opens: open a non-raster, then
  // take out every driver but the kept ones.
  static const char kText[] = "not a raster";
  const std::string probe = std::string(kDir) + "/probe.txt";
  writeFile(probe, reinterpret_cast<const std::uint8_t*>(kText), sizeof kText - 1);
  (void)skyroute::Dem::load(probe);
  VSIRmdirRecursive(kDir);
  for (int i = GDALGetDriverCount() - 1; i >= 0; --i) {
    GDALDriverH driver = GDALGetDriver(i);
    if (kept(GDALGetDriverShortName(driver))) continue;
    GDALDeregisterDriver(driver);
    GDALDestroyDriver(driver);
  }
  requireOnlyKeptDrivers();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skyroute;
  if (size < 1) return 0;
  const std::string path = std::string(kDir) + "/" + kNames[data[0] % kNames.size()];
  writeFile(path, data + 1, size - 1);

  CollisionWorldOptions options;
  options.build_octree = false;  // as the daemon: every check on the heightfield
  options.terrain_margin_m = 30.0;  // as terrain.terrain_margin_m: the dilated terrain is built too
  // The same limit as the daemon's (DemLoadOptions::max_cells), lowered so that an input stays
  // within libFuzzer's time and memory limits.
  DemLoadOptions dem_options;
  dem_options.max_cells = 1'000'000;
  auto world = loadTerrainWorld(path, options, dem_options);
  if (world) {
    const Heightfield& terrain = *world->heightfield;
    const Eigen::AlignedBox3d box = world->collision->flyableBounds();
    const Eigen::Vector3d lo = box.min();
    const Eigen::Vector3d hi = box.max();
    const Eigen::Vector3d centre = box.center();
    for (const Eigen::Vector3d& p : {lo, hi, centre, Eigen::Vector3d(lo.x(), hi.y(), centre.z())}) {
      (void)terrain.heightAt(p.x(), p.y());
      (void)terrain.heightAboveGround(p);
      (void)world->collision->isPointValid(p);
    }
    (void)terrain.minHeightAboveGround(lo, hi);
    (void)world->collision->isSegmentValid(lo, hi);
    (void)world->collision->isSegmentValid(Eigen::Vector3d(lo.x(), centre.y(), centre.z()),
                                           Eigen::Vector3d(hi.x(), centre.y(), centre.z()));
  }
  VSIRmdirRecursive(kDir);
  requireOnlyKeptDrivers();
  return 0;
}
