#include "service/no_fly_geojson.hpp"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "service/known_keys.hpp"
#include "service/no_fly_placement.hpp"

namespace skyroute {
namespace {

using nlohmann::json;

constexpr double kDefaultFloorAmslM = -1000.0;  // below any ground on Earth: the zone starts at the ground

Error parseError(const std::string& name, const std::string& what) {
  return make_error(ErrorCode::kParseError, name, what);
}

// The members a zone file may hold (docs/nofly.md): GeoJSON's own (RFC 7946: type, features,
// geometry, properties, coordinates, id, bbox), our properties, and at the top level the layer
// name and the GeoJSON 2008 crs that GDAL and QGIS write. Any other member, foreign members
// included, is refused: a misspelt one would otherwise be ignored.
const KnownKeys kCollectionKeys{"type", "features", "bbox", "name", "crs"};
const KnownKeys kDocumentFeatureKeys{"type", "geometry", "properties", "id", "bbox", "crs"};
const KnownKeys kFeatureKeys{"type", "geometry", "properties", "id", "bbox"};
const KnownKeys kGeometryKeys{"type", "coordinates", "bbox"};
const KnownKeys kZonePropertyKeys{"floor_m", "ceiling_m", "valid_from", "valid_until", "name"};

// An unknown member of `object` (at `path`, which the message names), with the error's field the
// feature as the file's other errors name it (`name`: "features[2] 'tower'").
std::optional<Error> unknownMember(const json& object, const KnownKeys& known, const std::string& path,
                                   const std::string& name) {
  auto unknown = unknownJsonKey(object, known, path, path);
  if (unknown) unknown->field = name;
  return unknown;
}

// A GeoJSON 2008 crs may only say what RFC 7946 assumes: WGS84 longitude, latitude (CRS84, or
// EPSG:4326 as GDAL writes it). Coordinates in any other CRS would be misread as degrees.
std::optional<Error> unusableCrs(const json& doc) {
  if (!doc.contains("crs")) return std::nullopt;
  const json& crs = doc["crs"];
  const json* name = nullptr;
  if (crs.is_object() && crs.contains("properties") && crs["properties"].is_object() &&
      crs["properties"].contains("name") && crs["properties"]["name"].is_string()) {
    name = &crs["properties"]["name"];
  }
  const std::string text = name ? name->get<std::string>() : "";
  auto ends = [&](const std::string& tail) {
    return text.size() >= tail.size() && text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
  };
  if (ends("CRS84") || (text.find("EPSG") != std::string::npos && ends(":4326"))) return std::nullopt;
  return parseError("geojson", "crs " + crs.dump(-1, ' ', false, json::error_handler_t::replace).substr(0, 200) +
                                   " is not WGS84 longitude, latitude (CRS84): GeoJSON (RFC 7946) coordinates are "
                                   "longitude, latitude in WGS84; write the zones so, without a crs");
}

// A GeoJSON "type" member as text: the string, or its JSON when it is not one ("" when absent).
// Not json::value("type", ""): it throws when the member is there but not a string.
std::string typeMember(const json& object) {
  const auto it = object.find("type");
  if (it == object.end()) return "";
  return it->is_string() ? it->get<std::string>() : it->dump(-1, ' ', false, json::error_handler_t::replace);
}

// The feature's id, or its name property ("" when it has neither).
std::string featureLabel(const json& feature) {
  if (!feature.is_object()) return "";
  const json* label = nullptr;
  if (feature.contains("id") && (feature["id"].is_string() || feature["id"].is_number())) label = &feature["id"];
  const json& props = feature.contains("properties") ? feature["properties"] : json();
  if (!label && props.is_object() && props.contains("name") && props["name"].is_string()) label = &props["name"];
  return label ? (label->is_string() ? label->get<std::string>() : label->dump()) : "";
}

// "features[2] 'tower'": the feature's index and label, as errors name it.
std::string featureName(const json& feature, std::size_t index) {
  const std::string label = featureLabel(feature);
  return "features[" + std::to_string(index) + "]" + (label.empty() ? "" : " '" + label + "'");
}

// UTC seconds from a number or an ISO 8601 UTC time ("2026-11-25T14:00:00Z", seconds optional).
Result<double> utcSeconds(const json& value, const std::string& name, const std::string& key) {
  if (value.is_number()) return value.get<double>();
  if (value.is_string()) {
    const std::string text = value.get<std::string>();
    std::tm tm{};
    int consumed = 0;
    double seconds = 0.0;
    const int got = std::sscanf(text.c_str(), "%4d-%2d-%2dT%2d:%2d%n", &tm.tm_year, &tm.tm_mon, &tm.tm_mday,
                                &tm.tm_hour, &tm.tm_min, &consumed);
    std::string rest = got == 5 ? text.substr(static_cast<std::size_t>(consumed)) : "";
    if (got == 5 && !rest.empty() && rest[0] == ':') {
      int more = 0;
      if (std::sscanf(rest.c_str(), ":%lf%n", &seconds, &more) == 1) rest = rest.substr(static_cast<std::size_t>(more));
    }
    if (got == 5 && rest == "Z") {
      tm.tm_year -= 1900;
      tm.tm_mon -= 1;
      return static_cast<double>(timegm(&tm)) + seconds;
    }
  }
  return parseError(name, key + " must be UTC seconds since the epoch or an ISO 8601 UTC time like "
                                "\"2026-11-25T14:00:00Z\"");
}

// A number property (nullopt when absent).
Result<std::optional<double>> numberProperty(const json& props, const std::string& key, const std::string& name) {
  if (!props.is_object() || !props.contains(key) || props[key].is_null()) return std::optional<double>();
  if (!props[key].is_number()) return parseError(name, key + " must be a number (metres AMSL)");
  return std::optional<double>(props[key].get<double>());
}

// The zone's heights and window from the feature's properties (no ring yet).
Result<NoFlyZone> zoneProperties(const json& feature, const std::string& name, const LocalFrame& frame) {
  const json props = feature.contains("properties") ? feature["properties"] : json();
  auto floor_amsl = numberProperty(props, "floor_m", name);
  if (!floor_amsl.ok()) return floor_amsl.error();
  auto ceiling_amsl = numberProperty(props, "ceiling_m", name);
  if (!ceiling_amsl.ok()) return ceiling_amsl.error();
  if (!*ceiling_amsl) return parseError(name, "has no ceiling_m property (metres AMSL)");
  NoFlyZone zone;
  zone.name = name;
  // The frame's up axis is altitude AMSL less the anchor's.
  zone.floor_m = floor_amsl->value_or(kDefaultFloorAmslM) - frame.anchor().alt_amsl_m;
  zone.ceiling_m = **ceiling_amsl - frame.anchor().alt_amsl_m;
  for (const char* key : {"valid_from", "valid_until"}) {
    if (!props.is_object() || !props.contains(key) || props[key].is_null()) continue;
    auto t = utcSeconds(props[key], name, key);
    if (!t.ok()) return t.error();
    (std::string(key) == "valid_from" ? zone.valid_from_s : zone.valid_until_s) = *t;
  }
  return zone;
}

// The outer ring of a polygon's coordinates ([[lon, lat], ...], closed or not) in ENU metres.
Result<std::vector<Eigen::Vector2d>> outerRing(const json& polygon, const std::string& name, const LocalFrame& frame) {
  if (!polygon.is_array() || polygon.empty() || !polygon[0].is_array()) {
    return parseError(name, "a polygon's coordinates must be an array of rings");
  }
  // Counted first, before any work on the positions (a closed ring repeats its first at the end).
  const json& positions = polygon[0];
  const bool closed = positions.size() > 1 && positions.front() == positions.back();
  const std::size_t vertices = positions.size() - (closed ? 1 : 0);
  if (vertices > kMaxNoFlyZoneVertices) {
    return make_error(ErrorCode::kInvalidArgument, name,
                      "ring has " + std::to_string(vertices) + " vertices, more than the " +
                          std::to_string(kMaxNoFlyZoneVertices) + " a zone may have");
  }
  std::vector<double> lon, lat;
  for (const json& position : polygon[0]) {
    if (!position.is_array() || position.size() < 2) {
      return parseError(name, "a position must be [longitude, latitude]");
    }
    // JSON has no NaN: a writer that had one leaves null or a string ("NaN") in its place.
    const bool numbers = position[0].is_number() && position[1].is_number();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    lon.push_back(numbers ? position[0].get<double>() : nan);
    lat.push_back(numbers ? position[1].get<double>() : nan);
  }
  std::vector<Eigen::Vector2d> ring;
  for (std::size_t i = 0; i < lon.size(); ++i) {
    if (!std::isfinite(lon[i]) || !std::isfinite(lat[i])) {
      return make_error(ErrorCode::kInvalidArgument, name,
                        "vertex " + std::to_string(i) + " is not a finite longitude, latitude (NaN)");
    }
    if (std::abs(lat[i]) > 90.0 || std::abs(lon[i]) > 180.0) {
      return make_error(ErrorCode::kInvalidArgument, name,
                        "vertex " + std::to_string(i) + " is out of range: longitude first, then latitude");
    }
  }
  frame.lonLatToEastNorth(lon.data(), lat.data(), lon.size());
  for (std::size_t i = 0; i < lon.size(); ++i) ring.emplace_back(lon[i], lat[i]);
  if (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();  // GeoJSON closes its rings
  return ring;
}

// The zones of one feature (one per polygon), checked (against the terrain too, when given).
// feature_keys: the members a feature may have where it stands (a lone Feature is the document).
Status addFeature(const json& feature, std::size_t index, const LocalFrame& frame, const Heightfield* terrain,
                  std::vector<NoFlyZone>& out, const KnownKeys& feature_keys) {
  const std::string name = featureName(feature, index);
  const std::string path = "features[" + std::to_string(index) + "]";
  if (auto unknown = unknownMember(feature, feature_keys, path, name)) return *unknown;
  if (!feature.is_object() || !feature.contains("geometry") || !feature["geometry"].is_object()) {
    return parseError(name, "is not a Feature with a geometry");
  }
  const json& geometry = feature["geometry"];
  if (auto unknown = unknownMember(geometry, kGeometryKeys, path + ".geometry", name)) return *unknown;
  if (feature.contains("properties")) {
    if (auto unknown = unknownMember(feature["properties"], kZonePropertyKeys, path + ".properties", name))
      return *unknown;
  }
  const std::string type = typeMember(geometry);
  if (!geometry.contains("coordinates") || !geometry["coordinates"].is_array()) {
    return parseError(name, "its geometry has no coordinates array");
  }
  std::vector<const json*> polygons;
  if (type == "Polygon") {
    polygons.push_back(&geometry["coordinates"]);
  } else if (type == "MultiPolygon") {
    for (const json& polygon : geometry["coordinates"]) polygons.push_back(&polygon);
  } else {
    return parseError(name, "geometry type '" + type + "' is not a Polygon or MultiPolygon");
  }
  auto base = zoneProperties(feature, name, frame);
  if (!base.ok()) return base.error();
  // The zone's id (what a mission error names and `skyroute nofly --lift` takes) is the feature's
  // label, or features[i] without one; errors about the file name both.
  const std::string label = featureLabel(feature);
  for (std::size_t k = 0; k < polygons.size(); ++k) {
    const std::string polygon = type == "MultiPolygon" ? " polygon " + std::to_string(k) : "";
    NoFlyZone zone = *base;
    zone.name = (label.empty() ? "features[" + std::to_string(index) + "]" : label) + polygon;
    auto ring = outerRing(*polygons[k], name + polygon, frame);
    if (!ring.ok()) return ring.error();
    zone.ring_m = std::move(*ring);
    if (auto bad = checkNoFlyZone(zone)) {
      bad->field = name + polygon;
      return *bad;
    }
    if (terrain) {
      if (auto off = zoneOffTerrainReason(zone, *terrain)) {
        return make_error(ErrorCode::kInvalidArgument, name + polygon,
                          *off + "; GeoJSON positions are [longitude, latitude]");
      }
    }
    out.push_back(std::move(zone));
  }
  return Status::success();
}

}  // namespace

Result<std::vector<NoFlyZone>> parseNoFlyGeoJson(const std::string& text, const LocalFrame& frame,
                                                 const Heightfield* terrain) {
  const json doc = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded()) return parseError("geojson", "is not valid JSON");
  if (!doc.is_object()) return parseError("geojson", "must be a FeatureCollection or a Feature object");
  const std::string type = typeMember(doc);
  std::vector<NoFlyZone> zones;
  if (auto crs = unusableCrs(doc)) return *crs;
  if (type == "Feature") {
    if (Status s = addFeature(doc, 0, frame, terrain, zones, kDocumentFeatureKeys); !s.ok()) return s.error();
    return zones;
  }
  if (type != "FeatureCollection" || !doc.contains("features") || !doc["features"].is_array()) {
    return parseError("geojson", "must be a FeatureCollection with a features array (or a single Feature)");
  }
  if (auto unknown = unknownJsonKey(doc, kCollectionKeys, "", "the FeatureCollection")) {
    unknown->field = "geojson";
    return *unknown;
  }
  for (std::size_t i = 0; i < doc["features"].size(); ++i) {
    if (Status s = addFeature(doc["features"][i], i, frame, terrain, zones, kFeatureKeys); !s.ok()) return s.error();
  }
  return zones;
}

Result<std::vector<NoFlyZone>> loadNoFlyGeoJson(const std::string& path, const LocalFrame& frame,
                                                const Heightfield* terrain) {
  std::ifstream in(path);
  if (!in) return make_error(ErrorCode::kFileNotFound, path, "cannot read the no-fly zone file " + path);
  std::ostringstream text;
  text << in.rdbuf();
  auto zones = parseNoFlyGeoJson(text.str(), frame, terrain);
  if (!zones.ok()) {
    Error e = zones.error();
    e.field = path + ": " + e.field;
    return e;
  }
  return zones;
}

}  // namespace skyroute
