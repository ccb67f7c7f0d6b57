#include "service/dds/no_fly_conversions.hpp"

#include <cmath>
#include <cstring>
#include <string>

#include <dds/dds.h>

#include "service/text_bounds.hpp"

namespace skyroute::dds {
namespace {

Error badMember(const std::string& member, const std::string& what) {
  return make_error(ErrorCode::kInvalidArgument, member, member + " " + what);
}

}  // namespace

void toWire(const NoFlyZoneData& in, skyroute_msgs_NoFlyZone& out) {
  out = skyroute_msgs_NoFlyZone{};
  out.zone_id = dds_string_dup(in.zone_id.c_str());
  const std::size_t n = in.ring.size();
  out.ring._length = out.ring._maximum = static_cast<uint32_t>(n);
  out.ring._release = n > 0;
  out.ring._buffer = n > 0 ? static_cast<skyroute_msgs_LatLon*>(dds_alloc(n * sizeof(skyroute_msgs_LatLon))) : nullptr;
  for (std::size_t i = 0; i < n; ++i) out.ring._buffer[i] = skyroute_msgs_LatLon{in.ring[i].lat_deg, in.ring[i].lon_deg};
  out.floor_amsl_m = in.floor_amsl_m;
  out.ceiling_amsl_m = in.ceiling_amsl_m;
  out.valid_from_utc_ns = in.valid_from_utc_ns;
  out.valid_until_utc_ns = in.valid_until_utc_ns;
  out.remove = in.remove;
}

Result<NoFlyZoneData> fromWire(const skyroute_msgs_NoFlyZone& in) {
  NoFlyZoneData out;
  if (auto bad = checkId(in.zone_id != nullptr ? std::string_view(in.zone_id) : std::string_view(), "zone_id"))
    return *bad;
  out.zone_id = in.zone_id;
  out.remove = in.remove;
  if (out.remove) return out;
  // Counted first, before any work on the vertices (the daemon's DDS thread converts this).
  if (in.ring._length > kMaxNoFlyZoneVertices) {
    return badMember("ring", "has " + std::to_string(in.ring._length) + " vertices, more than the " +
                                 std::to_string(kMaxNoFlyZoneVertices) + " a zone may have (zone '" + out.zone_id +
                                 "')");
  }
  out.ring.reserve(in.ring._length);
  for (uint32_t i = 0; i < in.ring._length; ++i) {
    const skyroute_msgs_LatLon& p = in.ring._buffer[i];
    const std::string member = "ring[" + std::to_string(i) + "]";
    if (!std::isfinite(p.lat_deg)) return badMember(member + ".lat_deg", "is not a finite number");
    if (!std::isfinite(p.lon_deg)) return badMember(member + ".lon_deg", "is not a finite number");
    out.ring.push_back(GeoPoint{p.lat_deg, p.lon_deg, 0.0});
  }
  if (!std::isfinite(in.floor_amsl_m)) return badMember("floor_amsl_m", "is not a finite number");
  if (!std::isfinite(in.ceiling_amsl_m)) return badMember("ceiling_amsl_m", "is not a finite number");
  out.floor_amsl_m = in.floor_amsl_m;
  out.ceiling_amsl_m = in.ceiling_amsl_m;
  out.valid_from_utc_ns = in.valid_from_utc_ns;
  out.valid_until_utc_ns = in.valid_until_utc_ns;
  return out;
}

}  // namespace skyroute::dds
