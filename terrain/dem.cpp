#include "terrain/dem.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>

#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <ogr_srs_api.h>

namespace skyroute {
namespace {

constexpr float kUnknown = std::numeric_limits<float>::quiet_NaN();

struct DatasetCloser {
  void operator()(void* ds) const { GDALClose(ds); }
};
using DatasetPtr = std::unique_ptr<void, DatasetCloser>;

struct SrsDeleter {
  void operator()(OGRSpatialReferenceH srs) const { OSRDestroySpatialReference(srs); }
};
using SrsPtr = std::unique_ptr<std::remove_pointer_t<OGRSpatialReferenceH>, SrsDeleter>;

// Metres per declared vertical unit; 0 when the unit is not a length we know.
double metresPerUnit(std::string unit) {
  std::transform(unit.begin(), unit.end(), unit.begin(), [](unsigned char c) { return std::tolower(c); });
  if (unit.empty() || unit == "m" || unit == "metre" || unit == "meter" || unit == "metres" || unit == "meters") return 1.0;
  if (unit == "ft" || unit == "foot" || unit == "feet" || unit == "international foot") return 0.3048;
  if (unit == "us survey foot" || unit == "us-ft" || unit == "ftus") return 1200.0 / 3937.0;
  if (unit == "km" || unit == "kilometre" || unit == "kilometer") return 1000.0;
  return 0.0;
}

double haversineM(double lon1, double lat1, double lon2, double lat2) {
  constexpr double kEarthRadiusM = 6371008.8;
  constexpr double kDeg = M_PI / 180.0;
  const double dlat = (lat2 - lat1) * kDeg;
  const double dlon = (lon2 - lon1) * kDeg;
  const double a = std::sin(dlat / 2) * std::sin(dlat / 2) +
                   std::cos(lat1 * kDeg) * std::cos(lat2 * kDeg) * std::sin(dlon / 2) * std::sin(dlon / 2);
  return 2.0 * kEarthRadiusM * std::asin(std::min(1.0, std::sqrt(a)));
}

// Fills each void (4-connected region of unknown cells) of at most max_cells cells with an inverse
// distance average of the nearest known cell in each of the 8 directions; larger voids stay unknown.
int fillSmallVoids(std::vector<float>& h, int width, int height, int max_cells) {
  std::vector<int> label(h.size(), -1);
  std::vector<int> stack;
  std::vector<int> region;
  int filled = 0;
  std::vector<std::pair<int, float>> fills;
  for (int start = 0; start < static_cast<int>(h.size()); ++start) {
    if (!std::isnan(h[start]) || label[start] >= 0) continue;
    region.clear();
    stack.push_back(start);
    label[start] = start;
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      region.push_back(i);
      const int x = i % width;
      const int y = i / width;
      const int nbr[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
      for (const auto& n : nbr) {
        if (n[0] < 0 || n[1] < 0 || n[0] >= width || n[1] >= height) continue;
        const int j = n[1] * width + n[0];
        if (std::isnan(h[j]) && label[j] < 0) {
          label[j] = start;
          stack.push_back(j);
        }
      }
    }
    if (static_cast<int>(region.size()) > max_cells) continue;
    for (const int i : region) {
      const int x = i % width;
      const int y = i / width;
      double weight_sum = 0.0;
      double value_sum = 0.0;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if (dx == 0 && dy == 0) continue;
          for (int step = 1;; ++step) {
            const int cx = x + dx * step;
            const int cy = y + dy * step;
            if (cx < 0 || cy < 0 || cx >= width || cy >= height) break;
            const float v = h[cy * width + cx];
            if (!std::isnan(v)) {
              const double d = step * std::hypot(dx, dy);
              weight_sum += 1.0 / d;
              value_sum += v / d;
              break;
            }
          }
        }
      }
      if (weight_sum > 0.0) fills.emplace_back(i, static_cast<float>(value_sum / weight_sum));
    }
  }
  for (const auto& [i, v] : fills) h[i] = v;
  filled = static_cast<int>(fills.size());
  return filled;
}

}  // namespace

Eigen::Vector2d Dem::pixelToCrs(double col, double row) const {
  const auto& g = geo_transform_;
  return {g[0] + col * g[1] + row * g[2], g[3] + col * g[4] + row * g[5]};
}

Eigen::Vector2d Dem::crsToPixel(double x, double y) const {
  const auto& g = inverse_transform_;
  return {g[0] + x * g[1] + y * g[2], g[3] + x * g[4] + y * g[5]};
}

Result<std::shared_ptr<const Dem>> Dem::load(const std::string& path, const DemLoadOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  // GDAL's stat rather than the file system's, so its virtual paths (/vsimem/, /vsizip/...) load too.
  VSIStatBufL stat;
  if (VSIStatL(path.c_str(), &stat) != 0) return make_error(ErrorCode::kFileNotFound, path, "no such file");
  if (VSI_ISDIR(stat.st_mode)) return make_error(ErrorCode::kNotARaster, path, "is a directory");

  static std::once_flag gdal_registered;
  std::call_once(gdal_registered, [] { GDALAllRegister(); });
  CPLPushErrorHandler(CPLQuietErrorHandler);
  DatasetPtr ds(GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
  const std::string gdal_message = CPLGetLastErrorMsg();
  CPLPopErrorHandler();
  if (!ds) {
    return make_error(ErrorCode::kNotARaster, path,
                      "GDAL cannot open it as a raster" + (gdal_message.empty() ? "" : " (" + gdal_message + ")"));
  }
  const int band_count = GDALGetRasterCount(ds.get());
  if (band_count < 1) return make_error(ErrorCode::kNotARaster, path, "has no raster band");
  int band_index = options.band;
  if (band_index == 0) {
    if (band_count > 1) {
      return make_error(ErrorCode::kBandAmbiguous, path,
                        "has " + std::to_string(band_count) + " bands and none was chosen (use band = 1.." +
                            std::to_string(band_count) + ")");
    }
    band_index = 1;
  }
  if (band_index < 1 || band_index > band_count) {
    return make_error(ErrorCode::kInvalidArgument, path,
                      "band " + std::to_string(band_index) + " does not exist (the raster has " +
                          std::to_string(band_count) + ")");
  }

  auto dem = std::make_shared<Dem>();
  dem->path_ = path;
  const char* wkt = GDALGetProjectionRef(ds.get());
  if (wkt == nullptr || *wkt == '\0') return make_error(ErrorCode::kNoCrs, path, "has no coordinate reference system");
  dem->crs_wkt_ = wkt;
  if (GDALGetGeoTransform(ds.get(), dem->geo_transform_.data()) != CE_None) {
    return make_error(ErrorCode::kNoCrs, path, "has no georeferencing (geotransform)");
  }
  dem->width_ = GDALGetRasterXSize(ds.get());
  dem->height_ = GDALGetRasterYSize(ds.get());
  if (dem->width_ < 2 || dem->height_ < 2) return make_error(ErrorCode::kNotARaster, path, "is smaller than 2 x 2 cells");
  if (static_cast<std::int64_t>(dem->width_) * dem->height_ > options.max_cells) {
    return make_error(ErrorCode::kInvalidArgument, path,
                      "is " + std::to_string(dem->width_) + " x " + std::to_string(dem->height_) +
                          " cells, more than the " + std::to_string(options.max_cells) + " this service loads");
  }

  GDALRasterBandH band = GDALGetRasterBand(ds.get(), band_index);
  const double units = metresPerUnit(GDALGetRasterUnitType(band) ? GDALGetRasterUnitType(band) : "");
  if (units == 0.0) {
    return make_error(ErrorCode::kInvalidArgument, path,
                      std::string("declares vertical unit '") + GDALGetRasterUnitType(band) + "', not a length");
  }
  int has_nodata = 0;
  const double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
  int has_scale = 0;
  int has_offset = 0;
  double scale = GDALGetRasterScale(band, &has_scale);
  double offset = GDALGetRasterOffset(band, &has_offset);
  if (!has_scale) scale = 1.0;
  if (!has_offset) offset = 0.0;

  std::vector<double> raw(static_cast<std::size_t>(dem->width_) * dem->height_);
  if (GDALRasterIO(band, GF_Read, 0, 0, dem->width_, dem->height_, raw.data(), dem->width_, dem->height_, GDT_Float64,
                   0, 0) != CE_None) {
    return make_error(ErrorCode::kNotARaster, path, std::string("cannot read band: ") + CPLGetLastErrorMsg());
  }
  dem->heights_m_.resize(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const double v = raw[i];
    const bool is_nodata = !std::isfinite(v) || (has_nodata && (v == nodata || (std::isnan(nodata) && std::isnan(v))));
    dem->heights_m_[i] = is_nodata ? kUnknown : static_cast<float>((v * scale + offset) * units);
  }
  raw = {};
  ds.reset();
  return finish(std::move(dem), options, started);
}

Result<std::shared_ptr<const Dem>> Dem::fromArray(int width, int height, std::vector<float> heights_m,
                                                  const std::array<double, 6>& geo_transform,
                                                  const std::string& crs_wkt, const std::string& name) {
  if (width < 2 || height < 2 || heights_m.size() != static_cast<std::size_t>(width) * height) {
    return make_error(ErrorCode::kInvalidArgument, name, "heights do not match width x height (at least 2 x 2)");
  }
  if (crs_wkt.empty()) return make_error(ErrorCode::kNoCrs, name, "has no coordinate reference system");
  auto dem = std::make_shared<Dem>();
  dem->path_ = name;
  dem->width_ = width;
  dem->height_ = height;
  dem->heights_m_ = std::move(heights_m);
  dem->geo_transform_ = geo_transform;
  dem->crs_wkt_ = crs_wkt;
  return finish(std::move(dem), DemLoadOptions{}, std::chrono::steady_clock::now());
}

Result<std::shared_ptr<const Dem>> Dem::finish(std::shared_ptr<Dem> dem, const DemLoadOptions& options,
                                              std::chrono::steady_clock::time_point started) {
  const std::string& path = dem->path_;
  if (!GDALInvGeoTransform(dem->geo_transform_.data(), dem->inverse_transform_.data())) {
    return make_error(ErrorCode::kNoCrs, path, "has a degenerate geotransform");
  }
  SrsPtr srs(OSRNewSpatialReference(nullptr));
  const char* wkt_ptr = dem->crs_wkt_.c_str();
  if (OSRSetFromUserInput(srs.get(), wkt_ptr) != OGRERR_NONE) {
    return make_error(ErrorCode::kNoCrs, path, "has a coordinate reference system GDAL cannot interpret");
  }
  dem->geographic_ = OSRIsGeographic(srs.get()) != 0;
  // Checked before any transformation is made: PROJ spends seconds searching for one from a
  // geocentric CRS with a made-up ellipsoid, only to find none.
  if (!dem->geographic_ && OSRIsProjected(srs.get()) == 0) {
    return make_error(ErrorCode::kNoCrs, path,
                      "has a CRS that is neither geographic nor projected (a DEM needs horizontal coordinates)");
  }
  const char* name = OSRGetName(srs.get());
  dem->crs_name_ = name ? name : "unnamed";
  const char* authority = OSRGetAuthorityName(srs.get(), nullptr);
  const char* code = OSRGetAuthorityCode(srs.get(), nullptr);
  if (authority && code) dem->crs_name_ += std::string(" (") + authority + ":" + code + ")";

  std::size_t known = 0;
  for (const float v : dem->heights_m_) known += std::isnan(v) ? 0 : 1;
  if (known == 0) return make_error(ErrorCode::kAllNodata, path, "every cell is nodata");

  dem->filled_void_cells_ = fillSmallVoids(dem->heights_m_, dem->width_, dem->height_, options.max_filled_void_cells);
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  int unknown = 0;
  for (const float v : dem->heights_m_) {
    if (std::isnan(v)) {
      ++unknown;
      continue;
    }
    lo = std::min(lo, static_cast<double>(v));
    hi = std::max(hi, static_cast<double>(v));
  }
  dem->unknown_cells_ = unknown;
  dem->min_height_m_ = lo;
  dem->max_height_m_ = hi;
  if (lo < options.min_plausible_height_m || hi > options.max_plausible_height_m) {
    return make_error(ErrorCode::kAbsurdHeights, path,
                      "heights from " + std::to_string(lo) + " m to " + std::to_string(hi) +
                          " m are outside the plausible range [" + std::to_string(options.min_plausible_height_m) +
                          ", " + std::to_string(options.max_plausible_height_m) + "] m");
  }

  // Ground size of a cell at the raster's centre, through WGS84.
  SrsPtr wgs84(OSRNewSpatialReference(nullptr));
  OSRSetWellKnownGeogCS(wgs84.get(), "WGS84");
  OSRSetAxisMappingStrategy(wgs84.get(), OAMS_TRADITIONAL_GIS_ORDER);
  OSRSetAxisMappingStrategy(srs.get(), OAMS_TRADITIONAL_GIS_ORDER);
  OGRCoordinateTransformationH to_wgs84 = OCTNewCoordinateTransformation(srs.get(), wgs84.get());
  if (to_wgs84 == nullptr) return make_error(ErrorCode::kNoCrs, path, "CRS cannot be transformed to WGS84");
  const double cx = dem->width_ / 2.0;
  const double cy = dem->height_ / 2.0;
  double xs[3];
  double ys[3];
  const Eigen::Vector2d p0 = dem->pixelToCrs(cx, cy);
  const Eigen::Vector2d p1 = dem->pixelToCrs(cx + 1, cy);
  const Eigen::Vector2d p2 = dem->pixelToCrs(cx, cy + 1);
  xs[0] = p0.x(); ys[0] = p0.y();
  xs[1] = p1.x(); ys[1] = p1.y();
  xs[2] = p2.x(); ys[2] = p2.y();
  int ok[3] = {0, 0, 0};
  const bool transformed = OCTTransformEx(to_wgs84, 3, xs, ys, nullptr, ok) && ok[0] && ok[1] && ok[2];
  OCTDestroyCoordinateTransformation(to_wgs84);
  if (!transformed) return make_error(ErrorCode::kNoCrs, path, "centre cannot be transformed to WGS84");
  dem->resolution_m_ = {haversineM(xs[0], ys[0], xs[1], ys[1]), haversineM(xs[0], ys[0], xs[2], ys[2])};
  dem->load_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return std::shared_ptr<const Dem>(std::move(dem));
}

}  // namespace skyroute
