#include "service/obstacle_feed.hpp"

#include <algorithm>
#include <cmath>
#include <istream>

#include <nlohmann/json.hpp>

#include "service/known_keys.hpp"
#include "service/mission_json.hpp"
#include "service/number_text.hpp"

namespace skyroute {

namespace {

using nlohmann::json;

std::int64_t secondsToNs(double s) { return static_cast<std::int64_t>(std::llround(s * 1e9)); }

// "key_deg": [lat, lon, alt AMSL] into `point`, and "key_m" set to 0 in `obstacle` so the ENU
// parser accepts it (placeIn() fills it later). Both spellings at once are an error.
std::optional<Error> takeGeoPosition(json& obstacle, const std::string& key, std::optional<GeoPoint>& point) {
  auto deg = obstacle.find(key + "_deg");
  if (deg == obstacle.end()) return std::nullopt;
  const std::string field = "obstacle." + key + "_deg";
  if (obstacle.contains(key + "_m")) {
    return Error{ErrorCode::kParseError, field, field + " and obstacle." + key + "_m are both given (give one)"};
  }
  const bool triple = deg->is_array() && deg->size() == 3 &&
                      std::all_of(deg->begin(), deg->end(), [](const json& v) { return v.is_number(); });
  if (!triple) return Error{ErrorCode::kParseError, field, field + " must be [lat_deg, lon_deg, alt_amsl_m]"};
  const GeoPoint p{(*deg)[0].get<double>(), (*deg)[1].get<double>(), (*deg)[2].get<double>()};
  if (!std::isfinite(p.lat_deg) || !std::isfinite(p.lon_deg) || !std::isfinite(p.alt_amsl_m)) {
    return Error{ErrorCode::kParseError, field, field + " must hold finite numbers"};
  }
  if (std::abs(p.lat_deg) > 90.0 || std::abs(p.lon_deg) > 180.0) {
    return Error{ErrorCode::kParseError, field,
                 field + " latitude " + numberText(p.lat_deg) + ", longitude " + numberText(p.lon_deg) +
                     " is not a WGS84 position (latitude within +-90, longitude within +-180)"};
  }
  point = p;
  obstacle[key + "_m"] = json::array({0.0, 0.0, 0.0});
  return std::nullopt;
}

// Parses one data line; an Error names the field.
Result<FeedEntry> parseEntry(const std::string& line) {
  const json j = json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return make_error(ErrorCode::kParseError, "line", "is not valid JSON");
  if (!j.is_object()) return make_error(ErrorCode::kParseError, "line", "must be a JSON object");
  if (auto unknown = unknownJsonKey(j, {"t_s", "obstacle", "valid_from_s", "valid_for_s"}, "", "update")) return *unknown;
  FeedEntry entry;
  auto t = j.find("t_s");
  if (t == j.end()) return make_error(ErrorCode::kParseError, "t_s", "t_s is missing");
  if (!t->is_number() || !std::isfinite(t->get<double>()) || t->get<double>() < 0.0)
    return make_error(ErrorCode::kParseError, "t_s", "t_s must be a finite number >= 0");
  entry.t_s = t->get<double>();
  if (entry.t_s > kFeedMaxTimeS)
    return make_error(ErrorCode::kParseError, "t_s", "t_s " + numberText(entry.t_s) + " is beyond the feed's horizon of " +
                                                         numberText(kFeedMaxTimeS) + " s (one week)");
  auto o = j.find("obstacle");
  if (o == j.end()) return make_error(ErrorCode::kParseError, "obstacle", "obstacle is missing");
  json obstacle = *o;
  if (obstacle.is_object()) {
    for (auto [key, point] : {std::pair{"position", &entry.geo.position}, std::pair{"from", &entry.geo.from},
                              std::pair{"to", &entry.geo.to}}) {
      if (auto e = takeGeoPosition(obstacle, key, *point)) return *e;
    }
  }
  auto update = obstacleFromJson(obstacle, "obstacle", {"position_deg", "from_deg", "to_deg"});
  if (!update) return update.error();
  entry.update = std::move(*update);
  if (auto f = j.find("valid_from_s"); f != j.end()) {
    if (!f->is_number() || !std::isfinite(f->get<double>()) || f->get<double>() < 0.0)
      return make_error(ErrorCode::kParseError, "valid_from_s", "valid_from_s must be a finite number >= 0");
    entry.valid_from_s = f->get<double>();
    if (entry.valid_from_s > kFeedMaxTimeS)
      return make_error(ErrorCode::kParseError, "valid_from_s", "valid_from_s " + numberText(entry.valid_from_s) +
                                                                    " is beyond the feed's horizon of " +
                                                                    numberText(kFeedMaxTimeS) + " s (one week)");
  }
  if (auto d = j.find("valid_for_s"); d != j.end() && !d->is_null()) {
    if (!d->is_number() || !std::isfinite(d->get<double>()) || !(d->get<double>() > 0.0))
      return make_error(ErrorCode::kParseError, "valid_for_s", "valid_for_s must be a positive number (or null)");
    entry.valid_for_s = d->get<double>();
    if (*entry.valid_for_s > kFeedMaxValidityS)
      return make_error(ErrorCode::kParseError, "valid_for_s", "valid_for_s " + numberText(*entry.valid_for_s) +
                                                                   " is longer than a year (" +
                                                                   numberText(kFeedMaxValidityS) + " s)");
  }
  return entry;
}

}  // namespace

ObstacleUpdateData FeedEntry::stamped(std::int64_t publish_utc_ns) const {
  ObstacleUpdateData u = update;
  u.valid_from_utc_ns = publish_utc_ns + secondsToNs(valid_from_s);
  // At least a nanosecond: a validity shorter than that still ends after it begins.
  u.valid_until_utc_ns =
      valid_for_s ? u.valid_from_utc_ns + std::max<std::int64_t>(1, secondsToNs(*valid_for_s)) : 0;
  if (u.obstacle.motion) u.obstacle.motion->start_time_s = static_cast<double>(u.valid_from_utc_ns) * 1e-9;
  return u;
}

void FeedEntry::placeIn(const LocalFrame& frame) {
  Obstacle& o = update.obstacle;
  if (o.motion) {
    if (geo.from) o.motion->from_m = frame.toEnu(*geo.from);
    if (geo.to) o.motion->to_m = frame.toEnu(*geo.to);
    o.center_m = o.motion->from_m;
  }
  if (geo.position) o.center_m = frame.toEnu(*geo.position);
}

bool ObstacleFeed::hasGeoPositions() const {
  return std::any_of(entries.begin(), entries.end(), [](const FeedEntry& e) { return e.geo.any(); });
}

FeedEntry FeedEntry::fromUpdate(const ObstacleUpdateData& update, double t_s, std::int64_t received_utc_ns) {
  FeedEntry entry;
  entry.t_s = t_s;
  entry.update = update;
  entry.update.valid_from_utc_ns = 0;
  entry.update.valid_until_utc_ns = 0;
  if (entry.update.obstacle.motion) entry.update.obstacle.motion->start_time_s = 0.0;
  // An update that took effect before it was heard is recorded as effective at once. Times beyond
  // what a feed line may hold (the wire allows centuries) are recorded as the longest it may.
  if (update.valid_from_utc_ns > received_utc_ns) {
    entry.valid_from_s =
        std::min(kFeedMaxTimeS, static_cast<double>(update.valid_from_utc_ns - received_utc_ns) * 1e-9);
  }
  if (update.valid_until_utc_ns != 0) {
    const double from_abs_ns = static_cast<double>(std::max(update.valid_from_utc_ns, received_utc_ns));
    const double duration_s = (static_cast<double>(update.valid_until_utc_ns) - from_abs_ns) * 1e-9;
    entry.valid_for_s = std::clamp(duration_s, 1e-3, kFeedMaxValidityS);
  }
  return entry;
}

Result<ObstacleFeed> parseObstacleFeed(std::istream& in, const std::string& source_name) {
  std::string line;
  std::size_t line_number = 0;
  // Header: the first non-blank line.
  bool have_header = false;
  ObstacleFeed feed;
  while (!have_header && std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const json header = json::parse(line, nullptr, false);
    // Not header.value("format", ...): it throws when "format" is there but not a string.
    const auto format = header.is_object() ? header.find("format") : header.end();
    if (!header.is_object() || format == header.end() || !format->is_string() ||
        format->get_ref<const std::string&>() != kObstacleFeedFormat)
      return make_error(ErrorCode::kParseError, source_name,
                        source_name + ":" + std::to_string(line_number) + ": not an obstacle feed (the first line must be " +
                            obstacleFeedHeaderLine() + ")");
    auto version = header.find("version");
    if (version == header.end() || !version->is_number_integer())
      return make_error(ErrorCode::kParseError, source_name,
                        source_name + ":" + std::to_string(line_number) + ": header has no integer version");
    // Compared as read: as an int, 4294967297 would pass for version 1.
    const std::int64_t version_number = version->get<std::int64_t>();
    if (version_number != kObstacleFeedVersion)
      return make_error(ErrorCode::kParseError, source_name,
                        source_name + ":" + std::to_string(line_number) + ": feed version " + std::to_string(version_number) +
                            " is not supported (this build reads version " + std::to_string(kObstacleFeedVersion) + ")");
    if (auto unknown = unknownJsonKey(header, {"format", "version"}, "", "header")) {
      return make_error(ErrorCode::kParseError, source_name,
                        source_name + ":" + std::to_string(line_number) + ": " + unknown->message);
    }
    feed.version = kObstacleFeedVersion;
    have_header = true;
  }
  if (!have_header)
    return make_error(ErrorCode::kParseError, source_name, source_name + ": empty file, no obstacle feed header");

  double last_t_s = 0.0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    auto entry = parseEntry(line);
    if (!entry) {
      feed.skipped.push_back(FeedIssue{line_number, source_name + ":" + std::to_string(line_number) + ": " +
                                                        entry.error().message + " (line skipped)"});
      continue;
    }
    if (entry->t_s < last_t_s) {
      feed.skipped.push_back(FeedIssue{line_number, source_name + ":" + std::to_string(line_number) +
                                                        ": t_s goes back in time (" + numberText(entry->t_s) +
                                                        " after " + numberText(last_t_s) + ") (line skipped)"});
      continue;
    }
    last_t_s = entry->t_s;
    feed.entries.push_back(std::move(*entry));
  }
  return feed;
}

Result<ObstacleFeed> readObstacleFeed(const std::string& path) {
  std::ifstream in(path);
  if (!in) return make_error(ErrorCode::kFileNotFound, path, path + ": cannot open the obstacle feed");
  return parseObstacleFeed(in, path);
}

std::string obstacleFeedHeaderLine() {
  return json{{"format", kObstacleFeedFormat}, {"version", kObstacleFeedVersion}}.dump();
}

std::string obstacleFeedEntryLine(const FeedEntry& entry) {
  json obstacle = obstacleToJson(entry.update);
  // WGS84 positions are written as the feed gave them.
  for (auto [key, point] : {std::pair{"position", &entry.geo.position}, std::pair{"from", &entry.geo.from},
                            std::pair{"to", &entry.geo.to}}) {
    if (!*point) continue;
    obstacle.erase(std::string(key) + "_m");
    obstacle[std::string(key) + "_deg"] = json::array({(*point)->lat_deg, (*point)->lon_deg, (*point)->alt_amsl_m});
  }
  json j{{"t_s", entry.t_s}, {"obstacle", obstacle}};
  if (entry.valid_from_s != 0.0) j["valid_from_s"] = entry.valid_from_s;
  if (entry.valid_for_s) j["valid_for_s"] = *entry.valid_for_s;
  return j.dump();
}

Result<ObstacleFeedWriter> ObstacleFeedWriter::open(const std::string& path) {
  std::ofstream out(path, std::ios::trunc);
  if (!out) return make_error(ErrorCode::kFileNotFound, path, path + ": cannot create the obstacle feed file");
  out << obstacleFeedHeaderLine() << '\n' << std::flush;
  if (!out) return make_error(ErrorCode::kInternal, path, path + ": write failed");
  return ObstacleFeedWriter(std::move(out), path);
}

Status ObstacleFeedWriter::append(const FeedEntry& entry) {
  out_ << obstacleFeedEntryLine(entry) << '\n' << std::flush;
  if (!out_) return make_error(ErrorCode::kInternal, path_, path_ + ": write failed");
  ++entries_;
  return Status::success();
}

Status writeObstacleFeed(const std::string& path, const std::vector<FeedEntry>& entries) {
  auto writer = ObstacleFeedWriter::open(path);
  if (!writer) return writer.error();
  for (const auto& e : entries) {
    Status s = writer->append(e);
    if (!s) return s;
  }
  return Status::success();
}

}  // namespace skyroute
