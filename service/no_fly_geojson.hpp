// No-fly zones from a GeoJSON file (RFC 7946: WGS84 longitude, latitude), into the terrain's ENU
// frame. A FeatureCollection (or a single Feature) whose features are Polygon or MultiPolygon
// geometries; every polygon of a MultiPolygon is a zone of its own. Each feature's properties:
//   floor_m, ceiling_m   altitude AMSL in metres (floor defaults to -1000, i.e. the ground up;
//                        ceiling is required)
//   valid_from, valid_until (optional) the zone is in force from valid_from (inclusive) until
//                        valid_until (exclusive): UTC seconds since the Unix epoch, or an ISO 8601
//                        UTC time "2026-11-25T14:00:00Z"
// A zone is named by the feature's "id" (or its "name" property) and index: "features[2] 'tower'".
// The outer ring of each polygon is the zone; holes are ignored (the zone covers them too, the
// safe reading). Every error is kParseError or kInvalidArgument naming the feature: a ring of more
// than kMaxNoFlyZoneVertices vertices (counted before any other work on it), fewer than 3
// distinct vertices, a self-intersection, (nearly) zero area, a coordinate that is not a finite
// number, or the floor above the ceiling; with a terrain, a zone that lies entirely off it
// (no_fly_placement.hpp). A member neither GeoJSON nor these properties define is refused, naming
// it and the member it most likely misspells (docs/nofly.md lists the members taken).
#pragma once

#include <string>
#include <vector>

#include "planning/core/result.hpp"
#include "terrain/local_frame.hpp"
#include "terrain/no_fly_zone.hpp"

namespace skyroute {

class Heightfield;

// The zones in `frame`. terrain (whose frame is `frame`), when given: a zone that lies entirely
// off it is refused.
Result<std::vector<NoFlyZone>> parseNoFlyGeoJson(const std::string& text, const LocalFrame& frame,
                                                 const Heightfield* terrain = nullptr);
// Reads and parses the file; errors name the file and the feature.
Result<std::vector<NoFlyZone>> loadNoFlyGeoJson(const std::string& path, const LocalFrame& frame,
                                                const Heightfield* terrain = nullptr);

}  // namespace skyroute
