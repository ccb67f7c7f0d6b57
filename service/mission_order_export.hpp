// An ordered mission written for GIS tools and ground stations: the legs between consecutive
// points in visiting order as straight 3D lines, or the points themselves, through GDAL's OGR
// drivers (CSV with the geometry as WKT, GeoJSON, KML), WGS84. Heights follow each format as the
// trajectory exports do (trajectory_export.hpp): GeoJSON z above the WGS 84 ellipsoid (RFC 7946),
// KML `absolute` and the CSV above sea level (AMSL); every feature names its datum.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "service/height_datum.hpp"
#include "terrain/local_frame.hpp"
#include "planning/core/result.hpp"

namespace skyroute {

// One mission point, listed in visiting order.
struct OrderedPoint {
  int point = 0;            // request numbering: 0 = begin, 1..N = points[0..N-1], N+1 = end
  std::string label;        // "begin", "points[0]", "end"
  GeoPoint geo;             // WGS84, altitude AMSL
  Eigen::Vector3d enu_m = Eigen::Vector3d::Zero();
};

enum class OrderGeometry { kLegs, kPoints };
std::string_view to_string(OrderGeometry geometry);            // "legs", "points"
std::optional<OrderGeometry> parseOrderGeometry(std::string_view text);

// driver: "CSV", "GeoJSON" or "KML". leg_costs_m[k]: the cost of the leg from visited[k] to
// visited[k + 1] by the order's metric (written as cost_m beside the straight 3D length).
// Errors name the path; GeoJSON needs the EGM96 grid (without it, an error and no file).
Status writeMissionOrder(const std::string& path, const std::string& driver, const std::vector<OrderedPoint>& visited,
                         const std::vector<double>& leg_costs_m, OrderGeometry geometry,
                         const GeoidOptions& geoid = {});

}  // namespace skyroute
