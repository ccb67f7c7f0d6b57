// The obstacle feed: written then read back unchanged; malformed lines are reported with their
// line numbers and skipped; a bad header is fatal; stamping and recording are inverse.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "service/obstacle_feed.hpp"

namespace skyroute {
namespace {

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()) + ".jsonl")).string();
}

std::vector<FeedEntry> tableOneFeed() {
  // Obstacles A, B, C of seed 003 Table 1 (ellipsoids moving back and forth), then a removal.
  std::vector<FeedEntry> entries;
  const struct {
    std::uint64_t id;
    double major_m, minor_m;
    Eigen::Vector3d from, to;
    double speed;
  } table[] = {{1, 1200, 1200, {4900, 5400, 300}, {10400, 5400, 300}, 60},
               {2, 1500, 1500, {9800, 6900, 300}, {2200, 6900, 300}, 70},
               {3, 1500, 1050, {6000, 6600, 300}, {11600, 11600, 300}, 80}};
  double t = 0.0;
  for (const auto& row : table) {
    FeedEntry e;
    e.t_s = t;
    t += 0.25;
    e.update.obstacle.id = row.id;
    e.update.obstacle.shape = ObstacleShape::kEllipsoid;
    e.update.obstacle.size_m = {row.major_m / 2, row.minor_m / 2, 200};
    e.update.obstacle.center_m = row.from;
    e.update.obstacle.motion = BackAndForth{row.from, row.to, row.speed, 0.0};
    e.valid_for_s = 600.0;
    entries.push_back(e);
  }
  FeedEntry still;
  still.t_s = 1.0;
  still.update.obstacle.id = 9;
  still.update.obstacle.shape = ObstacleShape::kCylinder;
  still.update.obstacle.size_m = {80, 0, 400};
  still.update.obstacle.center_m = {3000, 3000, 200};
  still.update.constant_velocity_enu_mps = Eigen::Vector3d(1.5, -2.0, 0.0);
  still.valid_from_s = 0.5;
  entries.push_back(still);
  FeedEntry removal;
  removal.t_s = 2.0;
  removal.update.obstacle.id = 2;
  removal.update.remove = true;
  entries.push_back(removal);
  return entries;
}

TEST(ObstacleFeed, WriteThenReadGivesTheSameEntries) {
  const std::string path = tempPath("feed_roundtrip");
  const auto entries = tableOneFeed();
  ASSERT_TRUE(writeObstacleFeed(path, entries).ok());
  auto feed = readObstacleFeed(path);
  std::remove(path.c_str());
  ASSERT_TRUE(feed.ok()) << feed.error().describe();
  EXPECT_TRUE(feed->skipped.empty());
  ASSERT_EQ(feed->entries.size(), entries.size());
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const FeedEntry& a = feed->entries[i];
    const FeedEntry& b = entries[i];
    EXPECT_EQ(a.t_s, b.t_s);
    EXPECT_EQ(a.valid_from_s, b.valid_from_s);
    EXPECT_EQ(a.valid_for_s, b.valid_for_s);
    EXPECT_EQ(a.update.remove, b.update.remove);
    EXPECT_EQ(a.update.obstacle.id, b.update.obstacle.id);
    EXPECT_EQ(a.update.motionKind(), b.update.motionKind());
    if (b.update.remove) continue;
    EXPECT_EQ(a.update.obstacle.shape, b.update.obstacle.shape);
    EXPECT_EQ(a.update.obstacle.size_m, b.update.obstacle.size_m);
    EXPECT_EQ(a.update.obstacle.center_m, b.update.obstacle.center_m);
    if (b.update.obstacle.motion) {
      EXPECT_EQ(a.update.obstacle.motion->from_m, b.update.obstacle.motion->from_m);
      EXPECT_EQ(a.update.obstacle.motion->to_m, b.update.obstacle.motion->to_m);
      EXPECT_EQ(a.update.obstacle.motion->speed_mps, b.update.obstacle.motion->speed_mps);
    }
    EXPECT_EQ(a.update.constant_velocity_enu_mps, b.update.constant_velocity_enu_mps);
  }
}

TEST(ObstacleFeed, MalformedLinesAreSkippedWithTheirLineNumbers) {
  const auto good = tableOneFeed();
  std::ostringstream text;
  text << obstacleFeedHeaderLine() << "\n";                                               // line 1
  text << obstacleFeedEntryLine(good[0]) << "\n";                                         // line 2
  text << "{\"t_s\": 0.5, \"obstacle\": {\"id\": 4, \"shape\": \"sph\n";                  // line 3: broken JSON
  text << "{\"t_s\": 0.6, \"obstacle\": {\"id\": 5, \"shape\": \"cone\", \"size_m\": [1,1,1], \"position_m\": [0,0,0]}}\n";  // 4
  text << "\n";                                                                           // line 5: blank, ignored
  text << "{\"obstacle\": {\"id\": 6, \"remove\": true}}\n";                              // line 6: no t_s
  text << "{\"t_s\": 0.7, \"obstacle\": {\"id\": 7, \"shape\": \"sphere\", \"size_m\": [-3,1,1], \"position_m\": [0,0,0]}}\n";  // 7
  text << obstacleFeedEntryLine(good[3]) << "\n";                                         // line 8 (t_s 1.0)
  text << "{\"t_s\": 0.1, \"obstacle\": {\"id\": 8, \"remove\": true}}\n";                // line 9: back in time
  std::istringstream in(text.str());
  auto feed = parseObstacleFeed(in, "test.jsonl");
  ASSERT_TRUE(feed.ok()) << feed.error().describe();
  ASSERT_EQ(feed->entries.size(), 2u);
  EXPECT_EQ(feed->entries[0].update.obstacle.id, 1u);
  EXPECT_EQ(feed->entries[1].update.obstacle.id, 9u);
  ASSERT_EQ(feed->skipped.size(), 5u);
  const std::size_t lines[] = {3, 4, 6, 7, 9};
  const char* mentions[] = {"JSON", "obstacle.shape", "t_s", "obstacle.size_m.x", "back in time"};
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(feed->skipped[i].line, lines[i]);
    EXPECT_NE(feed->skipped[i].message.find("test.jsonl:" + std::to_string(lines[i]) + ":"), std::string::npos)
        << feed->skipped[i].message;
    EXPECT_NE(feed->skipped[i].message.find(mentions[i]), std::string::npos) << feed->skipped[i].message;
  }
}

TEST(ObstacleFeed, TimesStayWithinTheWireNanoseconds) {
  // Times past the feed's horizon (a week; a year of validity) are refused: far larger ones would
  // overflow publish + valid_from + valid_for in int64 nanoseconds.
  const std::string obstacle = R"("obstacle":{"id":1,"shape":"sphere","size_m":[1,1,1],"position_m":[0,0,0]})";
  std::istringstream in(obstacleFeedHeaderLine() + "\n" +                             // line 1
                        "{\"t_s\":1e10," + obstacle + "}\n" +                         // line 2
                        "{\"t_s\":0," + obstacle + ",\"valid_from_s\":1e300}\n" +     // line 3
                        "{\"t_s\":0," + obstacle + ",\"valid_for_s\":2e9}\n" +        // line 4
                        "{\"t_s\":6e5," + obstacle + ",\"valid_for_s\":1e-12}\n");    // line 5: accepted
  auto feed = parseObstacleFeed(in, "times.jsonl");
  ASSERT_TRUE(feed.ok()) << feed.error().describe();
  ASSERT_EQ(feed->skipped.size(), 3u);
  const char* keys[] = {"t_s", "valid_from_s", "valid_for_s"};
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_NE(feed->skipped[i].message.find(keys[i]), std::string::npos) << feed->skipped[i].message;
  ASSERT_EQ(feed->entries.size(), 1u);
  // A validity shorter than a nanosecond still ends after it begins, so the daemon accepts it.
  const ObstacleUpdateData stamped = feed->entries[0].stamped(1'704'067'200'000'000'000);
  EXPECT_EQ(stamped.valid_until_utc_ns, stamped.valid_from_utc_ns + 1);
  EXPECT_FALSE(validateObstacleUpdate(stamped).has_value());
}

// The feed text is refused with a message that says this.
void expectFeedRefused(const std::string& text, const std::string& name, const std::string& says) {
  std::istringstream in(text);
  const auto r = parseObstacleFeed(in, name);
  ASSERT_FALSE(r.ok()) << text;
  EXPECT_NE(r.error().message.find(says), std::string::npos) << r.error().message;
}

TEST(ObstacleFeed, BadHeaderOrVersionIsFatal) {
  expectFeedRefused("{\"t_s\": 0, \"obstacle\": {\"id\": 1, \"remove\": true}}\n", "x.jsonl", "x.jsonl:1");
  expectFeedRefused("{\"format\":\"skyroute-obstacle-feed\",\"version\":2}\n", "y.jsonl", "version 2");
  expectFeedRefused("", "z.jsonl", "");
  // A header whose format is not a string is refused like any other (it used to throw).
  expectFeedRefused("{\"format\":1,\"version\":1}\n", "n.jsonl", "not an obstacle feed");
  // 2^32 + 1 is not version 1, though it is as a 32-bit int.
  expectFeedRefused("{\"format\":\"skyroute-obstacle-feed\",\"version\":4294967297}\n", "w.jsonl",
                    "version 4294967297");

  auto missing = readObstacleFeed("/nonexistent/feed.jsonl");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, ErrorCode::kFileNotFound);
  EXPECT_EQ(missing.error().field, "/nonexistent/feed.jsonl");
}

TEST(ObstacleFeed, StampingAndRecordingAreInverse) {
  const std::int64_t publish_ns = 1'790'000'000'250'000'000LL;
  for (const FeedEntry& e : tableOneFeed()) {
    const ObstacleUpdateData stamped = e.stamped(publish_ns);
    EXPECT_EQ(stamped.valid_from_utc_ns, publish_ns + static_cast<std::int64_t>(e.valid_from_s * 1e9));
    if (e.valid_for_s) {
      EXPECT_EQ(stamped.valid_until_utc_ns, stamped.valid_from_utc_ns + static_cast<std::int64_t>(*e.valid_for_s * 1e9));
    } else {
      EXPECT_EQ(stamped.valid_until_utc_ns, 0);
    }
    if (stamped.obstacle.motion) {  // the bounce starts from from_m when the update takes effect
      EXPECT_DOUBLE_EQ(stamped.obstacle.motion->start_time_s, static_cast<double>(stamped.valid_from_utc_ns) * 1e-9);
    }
    const FeedEntry recorded = FeedEntry::fromUpdate(stamped, e.t_s, publish_ns);
    EXPECT_EQ(recorded.t_s, e.t_s);
    EXPECT_NEAR(recorded.valid_from_s, e.valid_from_s, 1e-9);
    ASSERT_EQ(recorded.valid_for_s.has_value(), e.valid_for_s.has_value());
    if (e.valid_for_s) {
      EXPECT_NEAR(*recorded.valid_for_s, *e.valid_for_s, 1e-9);
    }
    EXPECT_EQ(obstacleFeedEntryLine(recorded), obstacleFeedEntryLine(e));
  }
}

TEST(ObstacleFeed, RecordingAnUpdateValidForCenturiesGivesALineThatReplays) {
  const std::int64_t heard_ns = 1'704'067'200'000'000'000;
  ObstacleUpdateData update;
  update.obstacle.id = 3;
  update.valid_from_utc_ns = std::numeric_limits<std::int64_t>::max() - 2;  // the year 2262
  update.valid_until_utc_ns = std::numeric_limits<std::int64_t>::max();
  const FeedEntry far = FeedEntry::fromUpdate(update, 0.0, heard_ns);
  EXPECT_EQ(far.valid_from_s, kFeedMaxTimeS);
  update.valid_from_utc_ns = std::numeric_limits<std::int64_t>::min();  // long past: effective at once
  const FeedEntry long_valid = FeedEntry::fromUpdate(update, 0.0, heard_ns);
  EXPECT_EQ(long_valid.valid_from_s, 0.0);
  EXPECT_EQ(long_valid.valid_for_s, kFeedMaxValidityS);
  for (const FeedEntry& e : {far, long_valid}) {
    std::istringstream line(obstacleFeedHeaderLine() + "\n" + obstacleFeedEntryLine(e) + "\n");
    auto feed = parseObstacleFeed(line, "recorded.jsonl");
    ASSERT_TRUE(feed.ok());
    EXPECT_EQ(feed->entries.size(), 1u) << (feed->skipped.empty() ? "" : feed->skipped[0].message);
  }
}

TEST(ObstacleFeed, ShippedSeed003FeedIsCleanAndMatchesTableOne) {
  auto feed = readObstacleFeed(std::string(SKYROUTE_DATA_DIR) + "/feeds/seed003_table1.jsonl");
  ASSERT_TRUE(feed.ok()) << feed.error().describe();
  EXPECT_TRUE(feed->skipped.empty());
  ASSERT_EQ(feed->entries.size(), 3u);
  // Table 1: initial and final points and speeds of obstacles A, B, C.
  const double speeds[] = {60, 70, 80};
  const Eigen::Vector2d finals[] = {{10400, 5400}, {2200, 6900}, {11600, 11600}};
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& motion = feed->entries[i].update.obstacle.motion;
    ASSERT_TRUE(motion.has_value());
    EXPECT_EQ(motion->speed_mps, speeds[i]);
    EXPECT_EQ(motion->to_m.head<2>(), finals[i]);
  }
}

// Positions in WGS84 (position_deg, from_deg, to_deg) beside the ENU ones: kept as given, written
// back as given, and placed in a frame as that frame's ENU; both spellings of one position, or a
// position that is not WGS84, skip the line naming the field.
TEST(ObstacleFeed, PositionsInDegreesArePlacedInTheDaemonsFrame) {
  std::istringstream in(
      "{\"format\":\"skyroute-obstacle-feed\",\"version\":1}\n"
      "{\"t_s\":0,\"obstacle\":{\"id\":1,\"shape\":\"sphere\",\"size_m\":[80,0,0],"
      "\"position_deg\":[46.95,15.06,1200]}}\n"
      "{\"t_s\":1,\"obstacle\":{\"id\":2,\"shape\":\"sphere\",\"size_m\":[80,0,0],\"motion\":\"back_and_forth\","
      "\"from_deg\":[46.93,15.05,1100],\"to_deg\":[46.94,15.10,1100],\"speed_mps\":30}}\n"
      "{\"t_s\":2,\"obstacle\":{\"id\":3,\"shape\":\"sphere\",\"size_m\":[80,0,0],"
      "\"position_deg\":[46.95,15.06,1200],\"position_m\":[0,0,0]}}\n"
      "{\"t_s\":3,\"obstacle\":{\"id\":4,\"shape\":\"sphere\",\"size_m\":[80,0,0],"
      "\"position_deg\":[146.95,15.06,1200]}}\n"
      "{\"t_s\":4,\"obstacle\":{\"id\":5,\"shape\":\"sphere\",\"size_m\":[80,0,0],\"position_m\":[10,20,30]}}\n");
  auto feed = parseObstacleFeed(in, "geo.jsonl");
  ASSERT_TRUE(feed.ok()) << feed.error().describe();
  ASSERT_EQ(feed->entries.size(), 3u);
  ASSERT_EQ(feed->skipped.size(), 2u);
  EXPECT_NE(feed->skipped[0].message.find("geo.jsonl:4: obstacle.position_deg and obstacle.position_m are both given"),
            std::string::npos)
      << feed->skipped[0].message;
  EXPECT_NE(feed->skipped[1].message.find("geo.jsonl:5: obstacle.position_deg latitude 146.95"), std::string::npos)
      << feed->skipped[1].message;
  EXPECT_TRUE(feed->hasGeoPositions());

  // Written back as given.
  const std::string line = obstacleFeedEntryLine(feed->entries[0]);
  EXPECT_NE(line.find("\"position_deg\":[46.95,15.06,1200"), std::string::npos) << line;
  EXPECT_EQ(line.find("position_m"), std::string::npos) << line;

  auto frame = LocalFrame::create(46.9, 15.1);
  ASSERT_TRUE(frame.ok());
  for (FeedEntry& e : feed->entries) e.placeIn(*frame);
  const Eigen::Vector3d at = frame->toEnu(GeoPoint{46.95, 15.06, 1200});
  EXPECT_LT((feed->entries[0].update.obstacle.center_m - at).norm(), 1e-6);
  EXPECT_GT(at.head<2>().norm(), 1000.0);  // not the placeholder
  EXPECT_NEAR(at.z(), 1200.0, 1e-6);
  const Obstacle& moving = feed->entries[1].update.obstacle;
  ASSERT_TRUE(moving.motion);
  EXPECT_LT((moving.motion->from_m - frame->toEnu(GeoPoint{46.93, 15.05, 1100})).norm(), 1e-6);
  EXPECT_LT((moving.motion->to_m - frame->toEnu(GeoPoint{46.94, 15.10, 1100})).norm(), 1e-6);
  EXPECT_EQ(moving.center_m, moving.motion->from_m);
  // ENU positions stay as they are.
  EXPECT_EQ(feed->entries[2].update.obstacle.center_m, Eigen::Vector3d(10, 20, 30));
}

}  // namespace
}  // namespace skyroute
