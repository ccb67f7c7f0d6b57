#include "service/map_image.hpp"

#include <algorithm>
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

Result<MapImage> MapImage::hillshade(const Dem& dem) {
  GDALAllRegister();
  GDALDriverH mem = GDALGetDriverByName("MEM");
  if (!mem) return make_error(ErrorCode::kInternal, "gdal", "MEM driver missing");
  DatasetPtr src(GDALCreate(mem, "", dem.width(), dem.height(), 1, GDT_Float32, nullptr));
  if (!src) return make_error(ErrorCode::kInternal, "gdal", "cannot create a MEM dataset");
  GDALSetGeoTransform(src.get(), const_cast<double*>(dem.geoTransform().data()));
  GDALSetProjection(src.get(), dem.crsWkt().c_str());
  GDALRasterBandH band = GDALGetRasterBand(src.get(), 1);
  GDALSetRasterNoDataValue(band, std::numeric_limits<double>::quiet_NaN());
  std::vector<float> cells = dem.cells();
  if (GDALRasterIO(band, GF_Write, 0, 0, dem.width(), dem.height(), cells.data(), dem.width(), dem.height(),
                   GDT_Float32, 0, 0) != CE_None) {
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
  std::vector<std::uint8_t> grey(static_cast<std::size_t>(dem.width()) * dem.height());
  if (GDALRasterIO(GDALGetRasterBand(shade.get(), 1), GF_Read, 0, 0, dem.width(), dem.height(), grey.data(),
                   dem.width(), dem.height(), GDT_Byte, 0, 0) != CE_None) {
    return make_error(ErrorCode::kInternal, "gdal", "cannot read the hillshade");
  }
  MapImage image;
  image.width_ = dem.width();
  image.height_ = dem.height();
  image.rgb_.resize(grey.size() * 3);
  // Tint by height (green lowlands to brown and white tops) under the shading, so a person reads
  // both relief and altitude.
  const double lo = dem.minHeightM();
  const double span = std::max(1.0, dem.maxHeightM() - lo);
  for (std::size_t i = 0; i < grey.size(); ++i) {
    const float h = cells[i];
    const double shade_f = (grey[i] == 0 ? 180 : grey[i]) / 255.0;
    double r = 90, g = 90, b = 200;  // unknown cells: blue-grey
    if (!std::isnan(h)) {
      const double f = std::clamp((h - lo) / span, 0.0, 1.0);
      r = 110 + 130 * f;
      g = 150 + 60 * f - 40 * f * f;
      b = 90 + 150 * f * f;
    }
    image.rgb_[3 * i + 0] = static_cast<std::uint8_t>(std::clamp(r * (0.35 + 0.85 * shade_f), 0.0, 255.0));
    image.rgb_[3 * i + 1] = static_cast<std::uint8_t>(std::clamp(g * (0.35 + 0.85 * shade_f), 0.0, 255.0));
    image.rgb_[3 * i + 2] = static_cast<std::uint8_t>(std::clamp(b * (0.35 + 0.85 * shade_f), 0.0, 255.0));
  }
  return image;
}

MapImage MapImage::blank(int width, int height, Rgb background) {
  MapImage image;
  image.width_ = std::max(1, width);
  image.height_ = std::max(1, height);
  image.rgb_.resize(static_cast<std::size_t>(image.width_) * image.height_ * 3);
  for (std::size_t i = 0; i < image.rgb_.size(); i += 3) {
    image.rgb_[i] = background.r;
    image.rgb_[i + 1] = background.g;
    image.rgb_[i + 2] = background.b;
  }
  return image;
}

void MapImage::setPixel(int x, int y, Rgb c) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  const std::size_t i = (static_cast<std::size_t>(y) * width_ + x) * 3;
  rgb_[i] = c.r;
  rgb_[i + 1] = c.g;
  rgb_[i + 2] = c.b;
}

void MapImage::drawDisc(const Eigen::Vector2d& center_px, double radius_px, Rgb c) {
  const int r = static_cast<int>(std::ceil(radius_px));
  const int cx = static_cast<int>(std::lround(center_px.x()));
  const int cy = static_cast<int>(std::lround(center_px.y()));
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx)
      if (dx * dx + dy * dy <= radius_px * radius_px) setPixel(cx + dx, cy + dy, c);
}

void MapImage::drawLine(const Eigen::Vector2d& from_px, const Eigen::Vector2d& to_px, Rgb c, int thickness) {
  if (!from_px.allFinite() || !to_px.allFinite()) return;
  const double length = (to_px - from_px).norm();
  const int steps = std::max(1, static_cast<int>(std::ceil(length * 2.0)));
  for (int k = 0; k <= steps; ++k) {
    const Eigen::Vector2d p = from_px + (to_px - from_px) * (static_cast<double>(k) / steps);
    if (thickness <= 1) {
      setPixel(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())), c);
    } else {
      drawDisc(p, 0.5 * thickness, c);
    }
  }
}

void MapImage::drawPathEn(const Heightfield& terrain, const std::vector<Eigen::Vector3d>& path_m, Rgb c,
                          int thickness) {
  for (std::size_t i = 1; i < path_m.size(); ++i) {
    drawLine(terrain.enToPixel(path_m[i - 1].x(), path_m[i - 1].y()), terrain.enToPixel(path_m[i].x(), path_m[i].y()),
             c, thickness);
  }
}

void MapImage::appendProfile(const std::vector<double>& values, const std::vector<double>& reference,
                             int panel_height) {
  if (values.size() < 2 || panel_height < 10) return;
  const int old_height = height_;
  height_ += panel_height;
  rgb_.resize(static_cast<std::size_t>(width_) * height_ * 3, 255);
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (const auto* series : {&values, &reference}) {
    for (double v : *series) {
      if (!std::isfinite(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (!(hi > lo)) hi = lo + 1.0;
  auto to_px = [&](std::size_t i, std::size_t n, double v) {
    const double x = 4.0 + (width_ - 8.0) * static_cast<double>(i) / static_cast<double>(n - 1);
    const double y = old_height + panel_height - 4.0 - (panel_height - 8.0) * (v - lo) / (hi - lo);
    return Eigen::Vector2d(x, y);
  };
  // Ground filled in brown, the flight line in red.
  for (std::size_t i = 0; i < reference.size(); ++i) {
    if (!std::isfinite(reference[i])) continue;
    const Eigen::Vector2d top = to_px(i, reference.size(), reference[i]);
    drawLine(top, Eigen::Vector2d(top.x(), old_height + panel_height - 1.0), Rgb{160, 120, 80}, 1);
  }
  for (std::size_t i = 1; i < values.size(); ++i) {
    drawLine(to_px(i - 1, values.size(), values[i - 1]), to_px(i, values.size(), values[i]), Rgb{220, 20, 20}, 2);
  }
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
