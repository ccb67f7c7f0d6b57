// Fuzzes the obstacle feed (`skyroute replay FILE`): JSON lines -> parseObstacleFeed, then what each
// accepted line becomes: the update stamped at publication, its trip to the daemon (toWire ->
// fromWire, which runs the daemon's validation), the world's view of it (worldObstacle and the
// obstacle's motion over the replanning horizon), and its own feed line, which must read back the
// same. A line the feed accepts must be accepted by the daemon too; anything else is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>

#include "service/dds/conversions.hpp"
#include "service/obstacle_feed.hpp"
#include "service/world_model.hpp"
#include "tests/fuzz/finding.hpp"
#include "tests/fuzz/obstacle_equal.hpp"
#include "tests/fuzz/world_obstacle_probe.hpp"

namespace {

// A fixed publication time (2024-01-01T00:00:00Z), so a run is reproducible.
constexpr std::int64_t kPublishUtcNs = 1'704'067'200'000'000'000;

[[noreturn]] void finding(const std::string& what) { skyroute::fuzz::reportFinding("obstacle_feed_fuzzer", what); }

void checkEntry(const skyroute::FeedEntry& entry) {
  using namespace skyroute;
  const ObstacleUpdateData update = entry.stamped(kPublishUtcNs);
  if (auto problem = validateObstacleUpdate(update)) finding("the daemon refuses an accepted line: " + problem->describe());

  dds::WireSample<skyroute_msgs_ObstacleUpdate> wire(&skyroute_msgs_ObstacleUpdate_desc);
  dds::toWire(update, wire.msg());
  auto received = dds::fromWire(wire.msg(), kPublishUtcNs);
  if (!received) finding("the daemon refuses the published update: " + received.error().describe());
  if (!fuzz::sameUpdate(*received, update)) finding("the update arrives changed over DDS");

  fuzz::probeWorldObstacle(*received, kPublishUtcNs);

  std::istringstream line(obstacleFeedHeaderLine() + "\n" + obstacleFeedEntryLine(entry) + "\n");
  auto again = parseObstacleFeed(line, "own-line");
  if (!again || again->entries.size() != 1) finding("an entry's own feed line does not read back");
  const FeedEntry& back = again->entries.front();
  if (back.t_s != entry.t_s || back.valid_from_s != entry.valid_from_s || back.valid_for_s != entry.valid_for_s ||
      !fuzz::sameUpdate(back.stamped(kPublishUtcNs), update))
    finding("an entry's own feed line reads back differently");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  auto feed = skyroute::parseObstacleFeed(in, "fuzz.jsonl");
  if (!feed) return 0;
  for (const skyroute::FeedEntry& entry : feed->entries) checkEntry(entry);
  return 0;
}
