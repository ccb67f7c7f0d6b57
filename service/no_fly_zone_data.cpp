#include "service/no_fly_zone_data.hpp"

#include <cmath>

#include "service/text_bounds.hpp"

namespace skyroute {
namespace {

constexpr double kNsPerS = 1e9;

}  // namespace

Result<NoFlyZone> toNoFlyZone(const NoFlyZoneData& data, const LocalFrame& frame) {
  // The id first: it names the zone in logs, answers and the journal (text_bounds.hpp).
  if (auto bad = checkId(data.zone_id, "zone_id")) return *bad;
  NoFlyZone zone;
  zone.name = data.zone_id;
  const std::string named = "zone '" + data.zone_id + "'";
  auto refuse = [&](const std::string& field, const std::string& what) {
    return make_error(ErrorCode::kInvalidArgument, field, named + ": " + what);
  };
  // Counted first, before any work on the vertices.
  if (data.ring.size() > kMaxNoFlyZoneVertices) {
    return refuse("ring", "ring has " + std::to_string(data.ring.size()) + " vertices, more than the " +
                              std::to_string(kMaxNoFlyZoneVertices) + " a zone may have");
  }
  std::vector<double> lon, lat;
  for (std::size_t i = 0; i < data.ring.size(); ++i) {
    const GeoPoint& p = data.ring[i];
    if (std::abs(p.lat_deg) > 90.0 || std::abs(p.lon_deg) > 180.0) {
      const std::string member = "ring[" + std::to_string(i) + "]";
      return refuse(member, member + " is not a latitude, longitude in range");
    }
    lon.push_back(p.lon_deg);
    lat.push_back(p.lat_deg);
  }
  // NaN passes the range test above; checkNoFlyRing names it. Only finite ones are projected.
  bool finite = true;
  for (std::size_t i = 0; i < lon.size(); ++i) finite = finite && std::isfinite(lon[i]) && std::isfinite(lat[i]);
  if (finite) frame.lonLatToEastNorth(lon.data(), lat.data(), lon.size());
  for (std::size_t i = 0; i < lon.size(); ++i) zone.ring_m.emplace_back(lon[i], lat[i]);
  if (zone.ring_m.size() > 1 && zone.ring_m.front() == zone.ring_m.back()) zone.ring_m.pop_back();
  if (auto bad = checkNoFlyRing(zone.ring_m)) return refuse("ring", bad->message);
  zone.floor_m = data.floor_amsl_m - frame.anchor().alt_amsl_m;
  zone.ceiling_m = data.ceiling_amsl_m - frame.anchor().alt_amsl_m;
  if (data.valid_from_utc_ns != 0) zone.valid_from_s = static_cast<double>(data.valid_from_utc_ns) / kNsPerS;
  if (data.valid_until_utc_ns != 0) zone.valid_until_s = static_cast<double>(data.valid_until_utc_ns) / kNsPerS;
  if (auto bad = checkNoFlyZone(zone)) {
    bad->field = named;
    return *bad;
  }
  return zone;
}

NoFlyZoneData toNoFlyZoneData(const NoFlyZone& zone, const LocalFrame& frame) {
  NoFlyZoneData data;
  data.zone_id = zone.name;
  std::vector<double> east, north;
  for (const Eigen::Vector2d& v : zone.ring_m) {
    east.push_back(v.x());
    north.push_back(v.y());
  }
  frame.eastNorthToLonLat(east.data(), north.data(), east.size());
  for (std::size_t i = 0; i < east.size(); ++i) data.ring.push_back(GeoPoint{north[i], east[i], 0.0});
  data.floor_amsl_m = zone.floor_m + frame.anchor().alt_amsl_m;
  data.ceiling_amsl_m = zone.ceiling_m + frame.anchor().alt_amsl_m;
  if (zone.valid_from_s) data.valid_from_utc_ns = static_cast<std::int64_t>(std::llround(*zone.valid_from_s * kNsPerS));
  if (zone.valid_until_s) data.valid_until_utc_ns = static_cast<std::int64_t>(std::llround(*zone.valid_until_s * kNsPerS));
  return data;
}

}  // namespace skyroute
