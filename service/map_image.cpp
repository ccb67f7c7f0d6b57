#include "service/map_image.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <cpl_string.h>
#include <gdal.h>
#include <gdal_utils.h>

namespace skyroute {
namespace {
struct DatasetCloser {
  void operator()(void* ds) const {
    if (ds) GDALClose(ds);
  }
};
using DatasetPtr = std::unique_ptr<void, DatasetCloser>;
}  // namespace

Result<MapImage> MapImage::hillshade(const Dem& dem) { return hillshade(dem, 0, 0, dem.width(), dem.height()); }

Result<MapImage> MapImage::hillshade(const Dem& dem, int col0, int row0, int cols, int rows) {
  col0 = std::clamp(col0, 0, dem.width() - 1);
  row0 = std::clamp(row0, 0, dem.height() - 1);
  cols = std::clamp(cols, 1, dem.width() - col0);
  rows = std::clamp(rows, 1, dem.height() - row0);
  GDALAllRegister();
  GDALDriverH mem = GDALGetDriverByName("MEM");
  if (!mem) return make_error(ErrorCode::kInternal, "gdal", "MEM driver missing");
  DatasetPtr src(GDALCreate(mem, "", cols, rows, 1, GDT_Float32, nullptr));
  if (!src) return make_error(ErrorCode::kInternal, "gdal", "cannot create a MEM dataset");
  std::array<double, 6> transform = dem.geoTransform();
  transform[0] += col0 * transform[1] + row0 * transform[2];
  transform[3] += col0 * transform[4] + row0 * transform[5];
  GDALSetGeoTransform(src.get(), transform.data());
  GDALSetProjection(src.get(), dem.crsWkt().c_str());
  GDALRasterBandH band = GDALGetRasterBand(src.get(), 1);
  GDALSetRasterNoDataValue(band, std::numeric_limits<double>::quiet_NaN());
  std::vector<float> cells(static_cast<std::size_t>(cols) * rows);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) cells[static_cast<std::size_t>(r) * cols + c] = dem.cell(col0 + c, row0 + r);
  }
  if (GDALRasterIO(band, GF_Write, 0, 0, cols, rows, cells.data(), cols, rows, GDT_Float32, 0, 0) != CE_None) {
    return make_error(ErrorCode::kInternal, "gdal", "cannot write the MEM dataset");
  }
  CPLStringList args;
  args.AddString("-of");
  args.AddString("MEM");
  args.AddString("-compute_edges");
  if (dem.isGeographic()) {  // degrees horizontally, metres vertically
    args.AddString("-s");
    args.AddString("111120");
  }
  GDALDEMProcessingOptions* options = GDALDEMProcessingOptionsNew(args.List(), nullptr);
  int usage_error = 0;
  DatasetPtr shade(GDALDEMProcessing("", src.get(), "hillshade", nullptr, options, &usage_error));
  GDALDEMProcessingOptionsFree(options);
  if (!shade) return make_error(ErrorCode::kInternal, "gdal", std::string("hillshade failed: ") + CPLGetLastErrorMsg());
  std::vector<std::uint8_t> grey(static_cast<std::size_t>(cols) * rows);
  if (GDALRasterIO(GDALGetRasterBand(shade.get(), 1), GF_Read, 0, 0, cols, rows, grey.data(), cols, rows, GDT_Byte,
                   0, 0) != CE_None) {
    return make_error(ErrorCode::kInternal, "gdal", "cannot read the hillshade");
  }
  MapImage image;
  image.width_ = cols;
  image.height_ = rows;
  image.rgb_.resize(grey.size() * 3);
  // Tint by height (green lowlands to brown and white tops) under the shading, so a person reads
  // both relief and altitude; the tint spans the heights shown.
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (float h : cells) {
    if (std::isnan(h)) continue;
    lo = std::min<double>(lo, h);
    hi = std::max<double>(hi, h);
  }
  if (!(hi >= lo)) lo = hi = 0.0;
  const double span = std::max(1.0, hi - lo);
  for (std::size_t i = 0; i < grey.size(); ++i) {
    const float h = cells[i];
    const double shade_f = (grey[i] == 0 ? 180 : grey[i]) / 255.0;
    double r = 90, g = 90, b = 200;  // unknown cells: blue-grey
    if (!std::isnan(h)) {
      // Green lowlands, tan slopes, pale tops.
      const double f = std::clamp((h - lo) / span, 0.0, 1.0);
      const double u = f < 0.5 ? 2.0 * f : 2.0 * f - 1.0;
      const double from[3] = {f < 0.5 ? 110.0 : 205.0, f < 0.5 ? 150.0 : 185.0, f < 0.5 ? 90.0 : 125.0};
      const double to[3] = {f < 0.5 ? 205.0 : 245.0, f < 0.5 ? 185.0 : 240.0, f < 0.5 ? 125.0 : 230.0};
      r = from[0] + (to[0] - from[0]) * u;
      g = from[1] + (to[1] - from[1]) * u;
      b = from[2] + (to[2] - from[2]) * u;
    }
    image.rgb_[3 * i + 0] = static_cast<std::uint8_t>(std::clamp(r * (0.35 + 0.85 * shade_f), 0.0, 255.0));
    image.rgb_[3 * i + 1] = static_cast<std::uint8_t>(std::clamp(g * (0.35 + 0.85 * shade_f), 0.0, 255.0));
    image.rgb_[3 * i + 2] = static_cast<std::uint8_t>(std::clamp(b * (0.35 + 0.85 * shade_f), 0.0, 255.0));
  }
  return image;
}

Rgb MapImage::pixel(int x, int y) const {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return Rgb{};
  const std::size_t i = (static_cast<std::size_t>(y) * width_ + x) * 3;
  return Rgb{rgb_[i], rgb_[i + 1], rgb_[i + 2]};
}

Status MapImage::savePng(const std::string& path) const {
  GDALAllRegister();
  GDALDriverH mem = GDALGetDriverByName("MEM");
  GDALDriverH png = GDALGetDriverByName("PNG");
  if (!mem || !png) return make_error(ErrorCode::kInternal, "gdal", "MEM or PNG driver missing");
  DatasetPtr ds(GDALCreate(mem, "", width_, height_, 3, GDT_Byte, nullptr));
  if (!ds) return make_error(ErrorCode::kInternal, "gdal", "cannot create the image");
  for (int b = 0; b < 3; ++b) {
    // Interleaved source: pixel spacing 3 bytes, line spacing 3 * width.
    if (GDALRasterIO(GDALGetRasterBand(ds.get(), b + 1), GF_Write, 0, 0, width_, height_,
                     const_cast<std::uint8_t*>(rgb_.data()) + b, width_, height_, GDT_Byte, 3, 3 * width_) != CE_None) {
      return make_error(ErrorCode::kInternal, "gdal", "cannot fill the image");
    }
  }
  DatasetPtr out(GDALCreateCopy(png, path.c_str(), ds.get(), FALSE, nullptr, nullptr, nullptr));
  if (!out) return make_error(ErrorCode::kInvalidArgument, path, std::string("cannot write PNG: ") + CPLGetLastErrorMsg());
  return Status::success();
}

}  // namespace skyroute
