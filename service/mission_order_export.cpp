#include "service/mission_order_export.hpp"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <memory>

namespace skyroute {

namespace {

struct DatasetCloser {
  void operator()(GDALDataset* ds) const { GDALClose(GDALDataset::ToHandle(ds)); }
};

Error exportError(const std::string& path, const std::string& what) {
  return make_error(ErrorCode::kInternal, path, path + ": " + what + " (" + CPLGetLastErrorMsg() + ")");
}

// The attributes of each geometry's features, in file order.
const std::vector<std::pair<const char*, OGRFieldType>>& fieldsOf(OrderGeometry geometry) {
  static const std::vector<std::pair<const char*, OGRFieldType>> kLegs = {
      {"leg", OFTInteger},          {"from_point", OFTInteger},   {"to_point", OFTInteger},
      {"from_label", OFTString},    {"to_label", OFTString},      {"from_lat_deg", OFTReal},
      {"from_lon_deg", OFTReal},    {"from_alt_amsl_m", OFTReal}, {"to_lat_deg", OFTReal},
      {"to_lon_deg", OFTReal},      {"to_alt_amsl_m", OFTReal},   {"cost_m", OFTReal},
      {"straight_m", OFTReal},      {"height_datum", OFTString}};
  static const std::vector<std::pair<const char*, OGRFieldType>> kPoints = {
      {"visit", OFTInteger},  {"point", OFTInteger},      {"label", OFTString},       {"lat_deg", OFTReal},
      {"lon_deg", OFTReal},   {"alt_amsl_m", OFTReal},    {"height_datum", OFTString}};
  return geometry == OrderGeometry::kLegs ? kLegs : kPoints;
}

// The z each format stores for the visited points.
Result<std::vector<double>> heightsFor(const std::string& driver, const std::vector<OrderedPoint>& visited,
                                       const GeoidOptions& geoid_options) {
  std::vector<GeoPoint> points;
  for (const OrderedPoint& p : visited) points.push_back(p.geo);
  if (driver == "GeoJSON") {
    auto geoid = Egm96Geoid::load(geoid_options);
    if (!geoid) return geoid.error();
    return geoid->ellipsoidHeightsM(points);
  }
  std::vector<double> amsl;
  for (const GeoPoint& p : points) amsl.push_back(p.alt_amsl_m);
  return amsl;
}

void setPointFields(OGRFeature& f, const std::string& prefix, const OrderedPoint& p) {
  f.SetField((prefix + "lat_deg").c_str(), p.geo.lat_deg);
  f.SetField((prefix + "lon_deg").c_str(), p.geo.lon_deg);
  f.SetField((prefix + "alt_amsl_m").c_str(), p.geo.alt_amsl_m);
}

}  // namespace

std::string_view to_string(OrderGeometry geometry) { return geometry == OrderGeometry::kLegs ? "legs" : "points"; }

std::optional<OrderGeometry> parseOrderGeometry(std::string_view text) {
  if (text == "legs") return OrderGeometry::kLegs;
  if (text == "points") return OrderGeometry::kPoints;
  return std::nullopt;
}

Status writeMissionOrder(const std::string& path, const std::string& driver_name,
                         const std::vector<OrderedPoint>& visited, const std::vector<double>& leg_costs_m,
                         OrderGeometry geometry, const GeoidOptions& geoid) {
  CPLStringList dataset_options, layer_options;
  if (driver_name == "GeoJSON") {
    layer_options.AddNameValue("RFC7946", "YES");
    layer_options.AddNameValue("COORDINATE_PRECISION", "9");
  } else if (driver_name == "KML") {
    dataset_options.AddNameValue("AltitudeMode", "absolute");  // else viewers clamp to the ground
  } else if (driver_name == "CSV") {
    layer_options.AddNameValue("GEOMETRY", "AS_WKT");
    layer_options.AddNameValue("STRING_QUOTING", "IF_NEEDED");
  } else {
    return make_error(ErrorCode::kInvalidArgument, path, "no mission export through the OGR driver '" + driver_name + "'");
  }
  if (geometry == OrderGeometry::kLegs && leg_costs_m.size() + 1 != visited.size()) {
    return make_error(ErrorCode::kInvalidArgument, path, "one leg cost per leg expected");
  }
  // Heights before the file: a missing geoid grid leaves no file without them.
  auto z = heightsFor(driver_name, visited, geoid);
  if (!z) return z.error();
  const char* datum = driver_name == "GeoJSON" ? kEllipsoidDatumName : kAmslDatumName;

  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driver_name.c_str());
  if (driver == nullptr) return make_error(ErrorCode::kInternal, path, "GDAL has no " + driver_name + " driver");
  std::unique_ptr<GDALDataset, DatasetCloser> ds(driver->Create(path.c_str(), 0, 0, 0, GDT_Unknown, dataset_options.List()));
  if (!ds) return exportError(path, "cannot create the " + driver_name + " file");
  OGRSpatialReference wgs84;
  wgs84.SetWellKnownGeogCS("WGS84");
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);  // longitude first, as the formats write
  const bool legs = geometry == OrderGeometry::kLegs;
  OGRLayer* layer = ds->CreateLayer(legs ? "legs" : "points", &wgs84, legs ? wkbLineString25D : wkbPoint25D,
                                    layer_options.List());
  if (layer == nullptr) return exportError(path, "cannot create the layer");
  for (const auto& [name, type] : fieldsOf(geometry)) {
    OGRFieldDefn defn(name, type);
    if (layer->CreateField(&defn) != OGRERR_NONE) return exportError(path, std::string("cannot create field ") + name);
  }

  const std::size_t count = legs ? visited.size() - 1 : visited.size();
  for (std::size_t k = 0; k < count; ++k) {
    OGRFeature feature(layer->GetLayerDefn());
    const OrderedPoint& a = visited[k];
    feature.SetField("height_datum", datum);
    if (legs) {
      const OrderedPoint& b = visited[k + 1];
      feature.SetField("leg", static_cast<int>(k));
      feature.SetField("from_point", a.point);
      feature.SetField("to_point", b.point);
      feature.SetField("from_label", a.label.c_str());
      feature.SetField("to_label", b.label.c_str());
      setPointFields(feature, "from_", a);
      setPointFields(feature, "to_", b);
      feature.SetField("cost_m", leg_costs_m[k]);
      feature.SetField("straight_m", (b.enu_m - a.enu_m).norm());
      if (feature.GetFieldIndex("Name") >= 0) feature.SetField("Name", (a.label + " -> " + b.label).c_str());
      OGRLineString line;
      line.addPoint(a.geo.lon_deg, a.geo.lat_deg, (*z)[k]);
      line.addPoint(b.geo.lon_deg, b.geo.lat_deg, (*z)[k + 1]);
      feature.SetGeometry(&line);
    } else {
      feature.SetField("visit", static_cast<int>(k));
      feature.SetField("point", a.point);
      feature.SetField("label", a.label.c_str());
      setPointFields(feature, "", a);
      if (feature.GetFieldIndex("Name") >= 0) feature.SetField("Name", a.label.c_str());
      OGRPoint point(a.geo.lon_deg, a.geo.lat_deg, (*z)[k]);
      feature.SetGeometry(&point);
    }
    if (layer->CreateFeature(&feature) != OGRERR_NONE) return exportError(path, "cannot write feature " + std::to_string(k));
  }
  return Status::success();
}

}  // namespace skyroute
