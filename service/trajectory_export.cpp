#include "service/trajectory_export.hpp"

#include <cstdio>
#include <fstream>
#include <memory>

#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

namespace skyroute {

namespace {

void writeRow(std::ostream& out, const TrajectorySampleData& s) {
  char line[512];
  std::snprintf(line, sizeof line, "%.3f,%.8f,%.8f,%.3f,%.3f,%.3f,%.3f,%.4f,%.4f,%.4f,%.3f", s.t_rel_s, s.geo.lat_deg,
                s.geo.lon_deg, s.geo.alt_amsl_m, s.position_enu_m.x(), s.position_enu_m.y(), s.position_enu_m.z(),
                s.velocity_enu_mps.x(), s.velocity_enu_mps.y(), s.velocity_enu_mps.z(), s.heading_deg);
  out << line;
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

}  // namespace

void writeTrajectoryCsv(std::ostream& out, const TrajectoryData& trajectory, bool header) {
  if (header) out << kTrajectoryDataCsvHeader << '\n';
  for (const auto& s : trajectory.samples) {
    writeRow(out, s);
    out << '\n';
  }
}

Status writeTrajectoriesCsv(const std::string& path, const std::vector<TrajectoryData>& trajectories) {
  std::ofstream out(path);
  if (!out) return make_error(ErrorCode::kFileNotFound, path, path + ": cannot create the CSV file");
  out << "vehicle_id," << kTrajectoryDataCsvHeader << '\n';
  for (const auto& t : trajectories)
    for (const auto& s : t.samples) {
      out << t.vehicle_id << ',';
      writeRow(out, s);
      out << '\n';
    }
  if (!out) return make_error(ErrorCode::kInternal, path, path + ": write failed");
  return Status::success();
}

Status writeTrajectoriesOgr(const std::string& path, const std::string& driver_name,
                            const std::vector<TrajectoryData>& trajectories) {
  GDALAllRegister();
  GDALDriverH driver = GDALGetDriverByName(driver_name.c_str());
  if (driver == nullptr) return make_error(ErrorCode::kInternal, path, "GDAL has no " + driver_name + " driver");
  std::unique_ptr<void, DatasetCloser> ds(GDALCreate(driver, path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!ds) return ogrError(path, "cannot create the " + driver_name + " file");

  std::unique_ptr<void, SrsReleaser> srs(OSRNewSpatialReference(nullptr));
  OSRSetWellKnownGeogCS(static_cast<OGRSpatialReferenceH>(srs.get()), "WGS84");
  // Longitude first, as GeoJSON and KML write coordinates.
  OSRSetAxisMappingStrategy(static_cast<OGRSpatialReferenceH>(srs.get()), OAMS_TRADITIONAL_GIS_ORDER);
  OGRLayerH layer = GDALDatasetCreateLayer(ds.get(), "trajectories", static_cast<OGRSpatialReferenceH>(srs.get()),
                                           wkbLineString25D, nullptr);
  if (layer == nullptr) return ogrError(path, "cannot create the layer");

  const std::pair<const char*, OGRFieldType> fields[] = {{"vehicle_id", OFTString}, {"plan_id", OFTString},
                                                         {"revision", OFTInteger}, {"request_id", OFTString},
                                                         {"duration_s", OFTReal},  {"samples", OFTInteger}};
  for (const auto& [name, type] : fields) {
    OGRFieldDefnH defn = OGR_Fld_Create(name, type);
    const OGRErr err = OGR_L_CreateField(layer, defn, TRUE);
    OGR_Fld_Destroy(defn);
    if (err != OGRERR_NONE) return ogrError(path, std::string("cannot create field ") + name);
  }

  for (const auto& t : trajectories) {
    std::unique_ptr<void, FeatureDestroyer> feature(OGR_F_Create(OGR_L_GetLayerDefn(layer)));
    auto* f = static_cast<OGRFeatureH>(feature.get());
    OGR_F_SetFieldString(f, 0, t.vehicle_id.c_str());
    OGR_F_SetFieldString(f, 1, t.plan_id.c_str());
    OGR_F_SetFieldInteger(f, 2, static_cast<int>(t.revision));
    OGR_F_SetFieldString(f, 3, t.request_id.c_str());
    OGR_F_SetFieldDouble(f, 4, t.samples.empty() ? 0.0 : t.samples.back().t_rel_s - t.samples.front().t_rel_s);
    OGR_F_SetFieldInteger(f, 5, static_cast<int>(t.samples.size()));
    OGRGeometryH line = OGR_G_CreateGeometry(wkbLineString25D);
    for (const auto& s : t.samples) OGR_G_AddPoint(line, s.geo.lon_deg, s.geo.lat_deg, s.geo.alt_amsl_m);
    OGR_F_SetGeometryDirectly(f, line);  // the feature owns it now
    if (OGR_L_CreateFeature(layer, f) != OGRERR_NONE) return ogrError(path, "cannot write the feature of " + t.vehicle_id);
  }
  return Status::success();
}

}  // namespace skyroute
