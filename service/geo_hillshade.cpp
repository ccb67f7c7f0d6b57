#include "service/geo_hillshade.hpp"

#include <array>
#include <atomic>
#include <memory>
#include <vector>

#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <gdal_utils.h>

#include "service/map_image.hpp"

namespace skyroute {
namespace {

constexpr int kMaxWidth_px = 2048;  // a larger DEM's picture is resampled down to this

struct CloseDataset {
  void operator()(GDALDatasetH ds) const { GDALClose(ds); }
};
using Dataset = std::unique_ptr<void, CloseDataset>;

// A unique name in GDAL's in-memory file system.
std::string memoryPath(const char* stem) {
  static std::atomic<unsigned> counter{0};
  return std::string("/vsimem/skyroute_") + stem + "_" + std::to_string(counter++) + ".png";
}

// The file's bytes, removing it.
Result<std::string> takeMemoryFile(const std::string& path) {
  vsi_l_offset length = 0;
  GByte* data = VSIGetMemFileBuffer(path.c_str(), &length, TRUE);  // TRUE: the buffer is ours to free
  if (!data) return make_error(ErrorCode::kInternal, path, "was not written");
  std::string bytes(reinterpret_cast<const char*>(data), static_cast<std::size_t>(length));
  CPLFree(data);
  VSIUnlink(path.c_str());
  return bytes;
}

// The hillshade in the DEM's own grid and CRS (shaded in true metres), as an RGB MEM dataset.
Result<Dataset> shadedInDemGrid(const Dem& dem) {
  auto image = MapImage::hillshade(dem);
  if (!image) return image.error();
  const std::string path = memoryPath("hillshade");
  if (Status saved = image->savePng(path); !saved) return saved.error();
  Dataset png(GDALOpen(path.c_str(), GA_ReadOnly));
  if (!png) return make_error(ErrorCode::kInternal, path, "cannot reopen the hillshade");
  Dataset rgb(GDALCreateCopy(GDALGetDriverByName("MEM"), "", png.get(), FALSE, nullptr, nullptr, nullptr));
  png.reset();
  VSIUnlink(path.c_str());
  if (!rgb) return make_error(ErrorCode::kInternal, "gdal", "cannot copy the hillshade to memory");
  GDALSetGeoTransform(rgb.get(), const_cast<double*>(dem.geoTransform().data()));
  GDALSetProjection(rgb.get(), dem.crsWkt().c_str());
  return rgb;
}

// The picture resampled onto a latitude/longitude grid, transparent outside the DEM.
Result<Dataset> warpToWgs84(GDALDatasetH source, int width_px) {
  CPLStringList args;
  for (const char* a : {"-of", "MEM", "-t_srs", "EPSG:4326", "-r", "bilinear", "-dstalpha"}) args.AddString(a);
  if (width_px > 0) {  // height 0: GDAL keeps the aspect
    args.AddString("-ts");
    args.AddString(std::to_string(width_px).c_str());
    args.AddString("0");
  }
  GDALWarpAppOptions* options = GDALWarpAppOptionsNew(args.List(), nullptr);
  int usage_error = 0;
  Dataset warped(GDALWarp("", nullptr, 1, &source, options, &usage_error));
  GDALWarpAppOptionsFree(options);
  if (!warped) return make_error(ErrorCode::kInternal, "gdal", std::string("warp to WGS84 failed: ") + CPLGetLastErrorMsg());
  return warped;
}

}  // namespace

Result<GeoPng> hillshadePngWgs84(const Dem& dem) {
  GDALAllRegister();
  auto shaded = shadedInDemGrid(dem);
  if (!shaded) return shaded.error();
  auto warped = warpToWgs84(shaded->get(), 0);
  if (warped && GDALGetRasterXSize(warped->get()) > kMaxWidth_px) warped = warpToWgs84(shaded->get(), kMaxWidth_px);
  if (!warped) return warped.error();
  const std::string path = memoryPath("geo_hillshade");
  Dataset png(GDALCreateCopy(GDALGetDriverByName("PNG"), path.c_str(), warped->get(), FALSE, nullptr, nullptr, nullptr));
  if (!png) return make_error(ErrorCode::kInternal, path, std::string("cannot write PNG: ") + CPLGetLastErrorMsg());
  png.reset();  // closing flushes the file
  auto bytes = takeMemoryFile(path);
  if (!bytes) return bytes.error();

  std::array<double, 6> t{};  // north-up: t[2] == t[4] == 0, t[5] < 0
  GDALGetGeoTransform(warped->get(), t.data());
  GeoPng out;
  out.png = std::move(*bytes);
  out.width_px = GDALGetRasterXSize(warped->get());
  out.height_px = GDALGetRasterYSize(warped->get());
  out.west_deg = t[0];
  out.north_deg = t[3];
  out.east_deg = t[0] + out.width_px * t[1];
  out.south_deg = t[3] + out.height_px * t[5];
  return out;
}

}  // namespace skyroute
