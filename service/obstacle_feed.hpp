// The obstacle feed file: a recording of obstacle updates with their timing, written by
// `skyroute record`, replayed by `skyroute replay`, shipped in data/ for the demo and the tests.
// Format (JSON lines, version 1; full description in docs/obstacle_feed.md):
//   {"format":"skyroute-obstacle-feed","version":1}
//   {"t_s":0.0,"obstacle":{"id":1,"shape":"ellipsoid","size_m":[600,600,300],...},"valid_for_s":120}
// Positions are ENU metres in the daemon's frame (position_m, from_m, to_m) or WGS84 degrees and
// metres AMSL (position_deg, from_deg, to_deg).
// t_s is the offset from the start of the feed at which the update is published. Validity times
// are relative to that moment, so a replay today means what the recording meant then.
// A malformed data line is reported with its line number and skipped; only a missing file or a
// bad header line is fatal.
#pragma once

#include <cstdint>
#include <fstream>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "planning/core/result.hpp"
#include "service/mission_types.hpp"
#include "terrain/local_frame.hpp"

namespace skyroute {

inline constexpr const char* kObstacleFeedFormat = "skyroute-obstacle-feed";
inline constexpr int kObstacleFeedVersion = 1;
// Times a feed may give, in seconds: publish offsets and delays up to a week (a replay that waits
// longer is a mistake, and 1e12 s would wait 31,700 years), validity up to a year (and within
// int64 nanoseconds). A line beyond them is reported with its number and skipped.
inline constexpr double kFeedMaxTimeS = 7.0 * 24 * 3600;
inline constexpr double kFeedMaxValidityS = 365.0 * 24 * 3600;

// Obstacle positions a feed gives in WGS84 (position_deg, from_deg, to_deg: latitude, longitude,
// altitude AMSL) instead of the daemon's ENU metres. They need the daemon's local frame, which the
// file does not know: placeIn() turns them into the update's ENU fields (0 until then).
struct FeedGeoPositions {
  std::optional<GeoPoint> position, from, to;
  bool any() const { return position || from || to; }
};

struct FeedEntry {
  double t_s = 0.0;             // publish time, seconds after the feed start (non-decreasing)
  ObstacleUpdateData update;    // geometry and motion; its *_utc_ns fields are not used here
  double valid_from_s = 0.0;    // the update takes effect this long after t_s
  std::optional<double> valid_for_s;  // and lasts this long (nullopt = until removed)
  FeedGeoPositions geo;         // positions given in WGS84, to place in a frame before publishing

  // The WGS84 positions as ENU in `frame` (a back-and-forth obstacle without a position starts
  // at its from point).
  void placeIn(const LocalFrame& frame);

  // The update as published at publish_utc_ns: absolute validity times, and a back-and-forth
  // motion that starts (at from_m) at valid_from (its world clock is UTC seconds).
  ObstacleUpdateData stamped(std::int64_t publish_utc_ns) const;
  // The entry for an update heard at received_utc_ns, t_s after the recording started.
  static FeedEntry fromUpdate(const ObstacleUpdateData& update, double t_s, std::int64_t received_utc_ns);
};

struct FeedIssue {
  std::size_t line = 0;  // 1-based line number in the file
  std::string message;   // names the field
};

struct ObstacleFeed {
  int version = kObstacleFeedVersion;
  std::vector<FeedEntry> entries;
  std::vector<FeedIssue> skipped;  // malformed lines, in file order

  bool hasGeoPositions() const;
};

// source_name is used in messages (the file path).
Result<ObstacleFeed> parseObstacleFeed(std::istream& in, const std::string& source_name);
Result<ObstacleFeed> readObstacleFeed(const std::string& path);

std::string obstacleFeedHeaderLine();
std::string obstacleFeedEntryLine(const FeedEntry& entry);

// Writes a feed line by line, flushing each, so an interrupted recording is still a valid feed.
class ObstacleFeedWriter {
 public:
  static Result<ObstacleFeedWriter> open(const std::string& path);
  Status append(const FeedEntry& entry);
  std::size_t entriesWritten() const { return entries_; }

 private:
  ObstacleFeedWriter(std::ofstream out, std::string path) : out_(std::move(out)), path_(std::move(path)) {}
  std::ofstream out_;
  std::string path_;
  std::size_t entries_ = 0;
};

Status writeObstacleFeed(const std::string& path, const std::vector<FeedEntry>& entries);

}  // namespace skyroute
