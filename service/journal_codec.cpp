#include "service/journal_codec.hpp"

#include <cstring>
#include <type_traits>

#include "service/mission_json.hpp"

namespace skyroute {

using nlohmann::json;

namespace {

constexpr std::uint32_t kTrajectoryRecordTag = 0x534b5452;  // "SKTR": a trajectory record
constexpr std::uint32_t kTrajectoryRecordVersion = 1;

class RecordWriter {
 public:
  template <typename T>
  void put(T value) {
    static_assert(std::is_arithmetic_v<T>);
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    bytes_.append(raw, sizeof(T));
  }
  void put(const std::string& text) {
    put(static_cast<std::uint32_t>(text.size()));
    bytes_ += text;
  }
  void put(const Eigen::Vector3d& v) {
    for (int i = 0; i < 3; ++i) put(v[i]);
  }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

// Reads what RecordWriter wrote; the first read past the end sets failed() and returns zeros.
class RecordReader {
 public:
  explicit RecordReader(const std::string& bytes) : bytes_(bytes) {}
  template <typename T>
  T get() {
    static_assert(std::is_arithmetic_v<T>);
    T value{};
    if (!take(sizeof(T))) return value;
    std::memcpy(&value, bytes_.data() + at_ - sizeof(T), sizeof(T));
    return value;
  }
  std::string text() {
    const auto size = get<std::uint32_t>();
    if (!take(size)) return {};
    return bytes_.substr(at_ - size, size);
  }
  Eigen::Vector3d vector3() {
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v[i] = get<double>();
    return v;
  }
  // A count of items of at least item_bytes each: larger than what is left means a corrupt record.
  std::uint32_t count(std::size_t item_bytes) {
    const auto n = get<std::uint32_t>();
    if (static_cast<std::size_t>(n) * item_bytes > bytes_.size() - at_) failed_ = true;
    return failed_ ? 0 : n;
  }
  bool failed() const { return failed_; }
  bool atEnd() const { return at_ == bytes_.size(); }

 private:
  bool take(std::size_t size) {
    if (failed_ || size > bytes_.size() - at_) {
      failed_ = true;
      return false;
    }
    at_ += size;
    return true;
  }
  const std::string& bytes_;
  std::size_t at_ = 0;
  bool failed_ = false;
};

constexpr std::size_t kSampleBytes = 8 + 8 + 9 * 8 + 8 + 3 * 8;

Error badRecord(const std::string& field, const std::string& message) {
  return make_error(ErrorCode::kParseError, field, field + ": " + message);
}

template <typename T>
Result<T> required(const json& j, const char* key, const std::string& what) {
  auto it = j.find(key);
  if (it == j.end()) return badRecord(what + "." + key, "is missing");
  try {
    return it->get<T>();
  } catch (const json::exception&) {
    return badRecord(what + "." + key, "has the wrong type");
  }
}

}  // namespace

std::string encodeTrajectory(const TrajectoryData& t) {
  RecordWriter w;
  w.put(kTrajectoryRecordTag);
  w.put(kTrajectoryRecordVersion);
  w.put(t.vehicle_id);
  w.put(t.plan_id);
  w.put(t.revision);
  w.put(t.request_id);
  w.put(t.created_utc_ns);
  w.put(static_cast<std::uint32_t>(t.visiting_order.size()));
  for (std::uint32_t point : t.visiting_order) w.put(point);
  w.put(static_cast<std::uint32_t>(t.legs.size()));
  for (const LegBoundaryData& leg : t.legs) {
    w.put(leg.from_point);
    w.put(leg.to_point);
    w.put(leg.start_s);
    w.put(leg.end_s);
  }
  w.put(static_cast<std::uint32_t>(t.samples.size()));
  for (const TrajectorySampleData& s : t.samples) {
    w.put(s.t_rel_s);
    w.put(s.utc_ns);
    w.put(s.position_enu_m);
    w.put(s.velocity_enu_mps);
    w.put(s.acceleration_enu_mps2);
    w.put(s.heading_deg);
    w.put(s.geo.lat_deg);
    w.put(s.geo.lon_deg);
    w.put(s.geo.alt_amsl_m);
  }
  return w.take();
}

Result<TrajectoryData> decodeTrajectory(const std::string& bytes) {
  RecordReader r(bytes);
  if (r.get<std::uint32_t>() != kTrajectoryRecordTag) return badRecord("trajectory", "is not a trajectory record");
  if (const auto version = r.get<std::uint32_t>(); version != kTrajectoryRecordVersion) {
    return badRecord("trajectory", "record version " + std::to_string(version) + " is not known (this build reads " +
                                       std::to_string(kTrajectoryRecordVersion) + ")");
  }
  TrajectoryData t;
  t.vehicle_id = r.text();
  t.plan_id = r.text();
  t.revision = r.get<std::uint32_t>();
  t.request_id = r.text();
  t.created_utc_ns = r.get<std::int64_t>();
  t.visiting_order.resize(r.count(4));
  for (std::uint32_t& point : t.visiting_order) point = r.get<std::uint32_t>();
  t.legs.resize(r.count(24));
  for (LegBoundaryData& leg : t.legs) {
    leg.from_point = r.get<std::uint32_t>();
    leg.to_point = r.get<std::uint32_t>();
    leg.start_s = r.get<double>();
    leg.end_s = r.get<double>();
  }
  t.samples.resize(r.count(kSampleBytes));
  for (TrajectorySampleData& s : t.samples) {
    s.t_rel_s = r.get<double>();
    s.utc_ns = r.get<std::int64_t>();
    s.position_enu_m = r.vector3();
    s.velocity_enu_mps = r.vector3();
    s.acceleration_enu_mps2 = r.vector3();
    s.heading_deg = r.get<double>();
    s.geo.lat_deg = r.get<double>();
    s.geo.lon_deg = r.get<double>();
    s.geo.alt_amsl_m = r.get<double>();
  }
  if (r.failed()) return badRecord("trajectory", "record is cut short (" + std::to_string(bytes.size()) + " bytes)");
  if (!r.atEnd()) return badRecord("trajectory", "record has bytes after its end");
  return t;
}

json obstacleRecordToJson(const ObstacleUpdateData& update) {
  json j = obstacleToJson(update);
  j["valid_from_utc_ns"] = update.valid_from_utc_ns;
  j["valid_until_utc_ns"] = update.valid_until_utc_ns;
  return j;
}

Result<ObstacleUpdateData> obstacleRecordFromJson(const json& j) {
  auto update = obstacleFromJson(j, "obstacle", {"valid_from_utc_ns", "valid_until_utc_ns"});
  if (!update.ok()) return update.error();
  auto from = required<std::int64_t>(j, "valid_from_utc_ns", "obstacle");
  if (!from.ok()) return from.error();
  auto until = required<std::int64_t>(j, "valid_until_utc_ns", "obstacle");
  if (!until.ok()) return until.error();
  update->valid_from_utc_ns = *from;
  update->valid_until_utc_ns = *until;
  return update;
}

json noFlyZoneToJson(const NoFlyZoneData& zone) {
  json ring = json::array();
  for (const GeoPoint& p : zone.ring) ring.push_back(json::array({p.lat_deg, p.lon_deg}));
  return json{{"zone_id", zone.zone_id},
              {"ring", ring},
              {"floor_amsl_m", zone.floor_amsl_m},
              {"ceiling_amsl_m", zone.ceiling_amsl_m},
              {"valid_from_utc_ns", zone.valid_from_utc_ns},
              {"valid_until_utc_ns", zone.valid_until_utc_ns}};
}

Result<NoFlyZoneData> noFlyZoneFromJson(const json& j) {
  if (!j.is_object()) return badRecord("zone", "must be an object");
  NoFlyZoneData zone;
  auto id = required<std::string>(j, "zone_id", "zone");
  auto ring = required<std::vector<std::vector<double>>>(j, "ring", "zone");
  auto floor = required<double>(j, "floor_amsl_m", "zone");
  auto ceiling = required<double>(j, "ceiling_amsl_m", "zone");
  auto from = required<std::int64_t>(j, "valid_from_utc_ns", "zone");
  auto until = required<std::int64_t>(j, "valid_until_utc_ns", "zone");
  for (const Error* e : {id.ok() ? nullptr : &id.error(), ring.ok() ? nullptr : &ring.error(),
                         floor.ok() ? nullptr : &floor.error(), ceiling.ok() ? nullptr : &ceiling.error(),
                         from.ok() ? nullptr : &from.error(), until.ok() ? nullptr : &until.error()}) {
    if (e) return *e;
  }
  zone.zone_id = *id;
  for (const std::vector<double>& vertex : *ring) {
    if (vertex.size() != 2) return badRecord("zone.ring", "a vertex must be [lat, lon]");
    zone.ring.push_back(GeoPoint{vertex[0], vertex[1], 0.0});
  }
  zone.floor_amsl_m = *floor;
  zone.ceiling_amsl_m = *ceiling;
  zone.valid_from_utc_ns = *from;
  zone.valid_until_utc_ns = *until;
  return zone;
}

json fleetStatusToJson(const FleetStatusData& s) {
  json allocation = json::array();
  for (const FleetVehicleAllocationData& a : s.allocation) {
    allocation.push_back(json{{"vehicle_id", a.vehicle_id}, {"tasks", a.tasks}, {"delay_s", a.delay_s}});
  }
  return json{{"request_id", s.request_id},
              {"state", static_cast<int>(s.state)},
              {"error_code", static_cast<int>(s.error_code)},
              {"field", s.field},
              {"message", s.message},
              {"allocation", allocation},
              {"makespan_steps", s.makespan_steps},
              {"makespan_s", s.makespan_s},
              {"min_separation_m", s.min_separation_m},
              {"achieved_separation_m", s.achieved_separation_m},
              {"separation_repairs", s.separation_repairs},
              {"planning_time_s", s.planning_time_s}};
}

Result<FleetStatusData> fleetStatusFromJson(const json& j) {
  if (!j.is_object()) return badRecord("fleet", "must be an object");
  try {
    FleetStatusData s;
    s.request_id = j.at("request_id").get<std::string>();
    s.state = static_cast<PlanState>(j.at("state").get<int>());
    s.error_code = static_cast<PlanErrorCode>(j.at("error_code").get<int>());
    s.field = j.at("field").get<std::string>();
    s.message = j.at("message").get<std::string>();
    for (const json& a : j.at("allocation")) {
      s.allocation.push_back(FleetVehicleAllocationData{a.at("vehicle_id").get<std::string>(),
                                                        a.at("tasks").get<std::vector<std::uint32_t>>(),
                                                        a.at("delay_s").get<double>()});
    }
    s.makespan_steps = j.at("makespan_steps").get<std::int32_t>();
    s.makespan_s = j.at("makespan_s").get<double>();
    s.min_separation_m = j.at("min_separation_m").get<double>();
    s.achieved_separation_m = j.at("achieved_separation_m").get<double>();
    s.separation_repairs = j.at("separation_repairs").get<std::uint32_t>();
    s.planning_time_s = j.at("planning_time_s").get<double>();
    return s;
  } catch (const json::exception& e) {
    return badRecord("fleet", std::string("is malformed: ") + e.what());
  }
}

}  // namespace skyroute
