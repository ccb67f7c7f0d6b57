#include "service/trajectory_export.hpp"

#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string_view>

namespace skyroute {

namespace {

void writeRow(std::ostream& out, const TrajectorySampleData& s, double alt_ellipsoid_m) {
  char line[512];
  std::snprintf(line, sizeof line, "%.3f,%.8f,%.8f,%.3f,%.3f,%.3f,%.3f,%.4f,%.4f,%.4f,%.3f,%.3f", s.t_rel_s,
                s.geo.lat_deg, s.geo.lon_deg, s.geo.alt_amsl_m, s.position_enu_m.x(), s.position_enu_m.y(),
                s.position_enu_m.z(), s.velocity_enu_mps.x(), s.velocity_enu_mps.y(), s.velocity_enu_mps.z(),
                s.heading_deg, alt_ellipsoid_m);
  out << line;
}

// A text field of a CSV row (RFC 4180): quoted when it holds a comma, a quote or a line break,
// and prefixed with ' when a spreadsheet would read it as a formula (=, +, -, @). Vehicle ids are
// bounded ids that need neither (text_bounds.hpp); a file written from any source stays one row
// per sample all the same.
std::string csvTextField(const std::string& text) {
  std::string field = text;
  if (!field.empty() && std::string_view("=+-@").find(field.front()) != std::string_view::npos) field.insert(0, "'");
  if (field.find_first_of(",\"\r\n") == std::string::npos) return field;
  std::string quoted = "\"";
  for (char c : field) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

Result<std::vector<double>> ellipsoidHeights(const TrajectoryData& trajectory, const Egm96Geoid& geoid) {
  std::vector<GeoPoint> points;
  points.reserve(trajectory.samples.size());
  for (const auto& s : trajectory.samples) points.push_back(s.geo);
  auto heights = geoid.ellipsoidHeightsM(points);
  if (!heights) {
    // Name the sample as the trajectory does, not as the bulk call's points[i].
    std::string field = heights.error().field;
    if (field.rfind("points[", 0) == 0) field = trajectory.vehicle_id + ".samples[" + field.substr(7);
    return make_error(heights.error().code, field, heights.error().message);
  }
  return heights;
}

Error ogrError(const std::string& path, const std::string& what) {
  return make_error(ErrorCode::kInternal, path, path + ": " + what + " (" + CPLGetLastErrorMsg() + ")");
}

struct DatasetCloser {
  void operator()(void* ds) const { GDALClose(ds); }
};
struct FeatureDestroyer {
  void operator()(void* f) const { OGR_F_Destroy(static_cast<OGRFeatureH>(f)); }
};
struct SrsReleaser {
  void operator()(void* s) const { OSRRelease(static_cast<OGRSpatialReferenceH>(s)); }
};

// Per format: the OGR creation options and the datum of z.
struct OgrFormat {
  bool ellipsoidal = false;
  bool line_styles = false;  // one colour per vehicle (GeoJSON has no styles)
  std::vector<const char*> dataset_options;
  std::vector<const char*> layer_options;
};

Result<OgrFormat> ogrFormat(const std::string& driver, const std::string& path) {
  OgrFormat format;
  if (driver == "GeoJSON") {
    // RFC 7946: WGS84 longitude, latitude, height above the ellipsoid; no "crs" member. Nine
    // decimals of a degree (~0.1 mm) instead of the driver's seven, as in the CSV.
    format.ellipsoidal = true;
    format.layer_options = {"RFC7946=YES", "COORDINATE_PRECISION=9", nullptr};
  } else if (driver == "KML") {
    // Without an altitude mode, viewers clamp the lines to the ground.
    format.dataset_options = {"AltitudeMode=absolute", nullptr};
    format.line_styles = true;
  } else {
    return make_error(ErrorCode::kInvalidArgument, path,
                      "no trajectory export through the OGR driver '" + driver + "' (GeoJSON or KML)");
  }
  if (format.dataset_options.empty()) format.dataset_options.push_back(nullptr);
  return format;
}

}  // namespace

std::string vehicleColourHex(std::size_t index) {
  // Well separated on a hillshade and on satellite imagery (no greys, no near-black).
  static constexpr std::array<const char*, 12> kPalette = {"#E6194B", "#3CB44B", "#4363D8", "#F58231",
                                                           "#911EB4", "#42D4F4", "#F032E6", "#BFEF45",
                                                           "#FFE119", "#469990", "#9A6324", "#800000"};
  if (index < kPalette.size()) return kPalette[index];
  // Beyond the palette: the golden angle spreads hues evenly however many vehicles there are;
  // saturation and value alternate so neighbours with close hues still differ.
  const std::size_t k = index - kPalette.size();
  const double hue = std::fmod(17.0 + 137.50776405 * static_cast<double>(k), 360.0);
  const double saturation = k % 2 == 0 ? 0.85 : 0.6;
  const double value = k % 3 == 0 ? 0.95 : (k % 3 == 1 ? 0.75 : 0.6);
  // HSV to RGB, each channel from its place on the hue circle.
  auto byte = [&](double n) {
    const double sector = std::fmod(n + hue / 60.0, 6.0);
    const double v = value - value * saturation * std::clamp(std::min(sector, 4.0 - sector), 0.0, 1.0);
    return static_cast<unsigned>(std::lround(v * 255.0));
  };
  char hex[8];
  std::snprintf(hex, sizeof hex, "#%02X%02X%02X", byte(5.0), byte(3.0), byte(1.0));
  return hex;
}

Status writeTrajectoryCsv(std::ostream& out, const TrajectoryData& trajectory, const Egm96Geoid& geoid, bool header) {
  auto heights = ellipsoidHeights(trajectory, geoid);
  if (!heights) return heights.error();
  if (header) out << kTrajectoryDataCsvHeader << '\n';
  for (std::size_t i = 0; i < trajectory.samples.size(); ++i) {
    writeRow(out, trajectory.samples[i], (*heights)[i]);
    out << '\n';
  }
  return Status::success();
}

Status writeTrajectoriesCsv(const std::string& path, const std::vector<TrajectoryData>& trajectories,
                            const GeoidOptions& geoid_options) {
  // Every height first: a missing grid or a bad sample leaves no half-written file behind.
  auto geoid = Egm96Geoid::load(geoid_options);
  if (!geoid) return geoid.error();
  std::vector<std::vector<double>> heights;
  for (const auto& t : trajectories) {
    auto h = ellipsoidHeights(t, *geoid);
    if (!h) return h.error();
    heights.push_back(std::move(*h));
  }
  std::ofstream out(path);
  if (!out) return make_error(ErrorCode::kFileNotFound, path, path + ": cannot create the CSV file");
  out << "vehicle_id," << kTrajectoryDataCsvHeader << '\n';
  for (std::size_t k = 0; k < trajectories.size(); ++k)
    for (std::size_t i = 0; i < trajectories[k].samples.size(); ++i) {
      out << csvTextField(trajectories[k].vehicle_id) << ',';
      writeRow(out, trajectories[k].samples[i], heights[k][i]);
      out << '\n';
    }
  if (!out) return make_error(ErrorCode::kInternal, path, path + ": write failed");
  return Status::success();
}

Status writeGeoSamplesCsv(const std::string& path, std::vector<GeoSample> samples, const GeoidOptions& geoid_options) {
  auto geoid = Egm96Geoid::load(geoid_options);
  if (!geoid) return geoid.error();
  std::vector<GeoPoint> points;
  points.reserve(samples.size());
  for (const auto& s : samples) points.push_back(GeoPoint{s.lat_deg, s.lon_deg, s.alt_amsl_m});
  auto heights = geoid->ellipsoidHeightsM(points);
  if (!heights) return heights.error();
  for (std::size_t i = 0; i < samples.size(); ++i) samples[i].alt_ellipsoid_m = (*heights)[i];
  return writeTrajectoryCsv(path, samples);
}

Status writeTrajectoriesOgr(const std::string& path, const std::string& driver_name,
                            const std::vector<TrajectoryData>& trajectories, const GeoidOptions& geoid_options) {
  auto format = ogrFormat(driver_name, path);
  if (!format) return format.error();
  // Heights before the file: a missing grid must not leave a file without them.
  std::vector<std::vector<double>> z(trajectories.size());
  if (format->ellipsoidal) {
    auto geoid = Egm96Geoid::load(geoid_options);
    if (!geoid) return geoid.error();
    for (std::size_t k = 0; k < trajectories.size(); ++k) {
      auto h = ellipsoidHeights(trajectories[k], *geoid);
      if (!h) return h.error();
      z[k] = std::move(*h);
    }
  } else {
    for (std::size_t k = 0; k < trajectories.size(); ++k)
      for (const auto& s : trajectories[k].samples) z[k].push_back(s.geo.alt_amsl_m);
  }

  GDALAllRegister();
  GDALDriverH driver = GDALGetDriverByName(driver_name.c_str());
  if (driver == nullptr) return make_error(ErrorCode::kInternal, path, "GDAL has no " + driver_name + " driver");
  std::unique_ptr<void, DatasetCloser> ds(
      GDALCreate(driver, path.c_str(), 0, 0, 0, GDT_Unknown, const_cast<char**>(format->dataset_options.data())));
  if (!ds) return ogrError(path, "cannot create the " + driver_name + " file");

  std::unique_ptr<void, SrsReleaser> srs(OSRNewSpatialReference(nullptr));
  OSRSetWellKnownGeogCS(static_cast<OGRSpatialReferenceH>(srs.get()), "WGS84");
  // Longitude first, as GeoJSON and KML write coordinates.
  OSRSetAxisMappingStrategy(static_cast<OGRSpatialReferenceH>(srs.get()), OAMS_TRADITIONAL_GIS_ORDER);
  OGRLayerH layer = GDALDatasetCreateLayer(ds.get(), "trajectories", static_cast<OGRSpatialReferenceH>(srs.get()),
                                           wkbLineString25D, const_cast<char**>(format->layer_options.data()));
  if (layer == nullptr) return ogrError(path, "cannot create the layer");

  const std::pair<const char*, OGRFieldType> fields[] = {
      {"vehicle_id", OFTString}, {"plan_id", OFTString},  {"revision", OFTInteger},   {"request_id", OFTString},
      {"duration_s", OFTReal},   {"samples", OFTInteger}, {"height_datum", OFTString}};
  for (const auto& [name, type] : fields) {
    OGRFieldDefnH defn = OGR_Fld_Create(name, type);
    const OGRErr err = OGR_L_CreateField(layer, defn, TRUE);
    OGR_Fld_Destroy(defn);
    if (err != OGRERR_NONE) return ogrError(path, std::string("cannot create field ") + name);
  }

  const char* datum = format->ellipsoidal ? kEllipsoidDatumName : kAmslDatumName;
  for (std::size_t k = 0; k < trajectories.size(); ++k) {
    const TrajectoryData& t = trajectories[k];
    std::unique_ptr<void, FeatureDestroyer> feature(OGR_F_Create(OGR_L_GetLayerDefn(layer)));
    auto* f = static_cast<OGRFeatureH>(feature.get());
    // By name: some drivers add fields of their own (KML puts Name and Description first).
    auto set_string = [f](const char* name, const std::string& value) {
      OGR_F_SetFieldString(f, OGR_F_GetFieldIndex(f, name), value.c_str());
    };
    set_string("vehicle_id", t.vehicle_id);
    set_string("plan_id", t.plan_id);
    OGR_F_SetFieldInteger(f, OGR_F_GetFieldIndex(f, "revision"), static_cast<int>(t.revision));
    set_string("request_id", t.request_id);
    OGR_F_SetFieldDouble(f, OGR_F_GetFieldIndex(f, "duration_s"),
                         t.samples.empty() ? 0.0 : t.samples.back().t_rel_s - t.samples.front().t_rel_s);
    OGR_F_SetFieldInteger(f, OGR_F_GetFieldIndex(f, "samples"), static_cast<int>(t.samples.size()));
    set_string("height_datum", datum);
    if (OGR_F_GetFieldIndex(f, "Name") >= 0) set_string("Name", t.vehicle_id);  // the KML placemark's label
    if (format->line_styles) {
      const std::string style = "PEN(c:" + vehicleColourHex(k) + "FF,w:4px)";
      OGR_F_SetStyleString(f, style.c_str());
    }
    OGRGeometryH line = OGR_G_CreateGeometry(wkbLineString25D);
    for (std::size_t i = 0; i < t.samples.size(); ++i)
      OGR_G_AddPoint(line, t.samples[i].geo.lon_deg, t.samples[i].geo.lat_deg, z[k][i]);
    OGR_F_SetGeometryDirectly(f, line);  // the feature owns it now
    if (OGR_L_CreateFeature(layer, f) != OGRERR_NONE)
      return ogrError(path, "cannot write the feature of " + t.vehicle_id);
  }
  return Status::success();
}

}  // namespace skyroute
