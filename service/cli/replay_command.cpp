// skyroute replay: publishes a recorded obstacle feed with its original timing (scaled by
// --speed) or at a fixed --rate, once, or --loop until Ctrl-C or --duration. Malformed lines are
// reported and skipped. Obstacles the feed places in WGS84 (position_deg) are put in the local
// frame of --dem, which must be the daemon's DEM (by default both use the embedded terrain).
#include <chrono>
#include <iostream>

#include <CLI/CLI.hpp>

#include "service/cli/dds_cli_common.hpp"
#include "service/cli/dds_commands.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/obstacle_feed.hpp"
#include "service/shipped_data.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute::cli {

namespace {

struct ReplayOptions {
  int domain = 0;
  std::string input;
  std::string dem;  // "" = the embedded default terrain (shipped data)
  double speed = 1.0;
  bool loop = false;
  int readers = 0;
  double wait_s = 10.0;
  double rate = 0.0;       // updates per second, ignoring the feed's t_s (0 = the feed's timing)
  double duration_s = 0.0; // stop after this long (0 = at the end, or never with --loop)
};

void runReplay(const ReplayOptions& o) {
  const std::string tool = "replay";
  auto feed = readObstacleFeed(o.input);
  if (!feed) fail(tool, kExitBadInput, feed.error().message);
  for (const FeedIssue& issue : feed->skipped) std::cerr << "skyroute replay: " << issue.message << std::endl;
  if (feed->entries.empty()) fail(tool, kExitBadInput, o.input + ": no valid obstacle updates to replay");
  if (feed->hasGeoPositions()) {
    // The daemon's frame: anchored at its DEM's centre (terrain/heightfield.hpp).
    std::string dem_path = o.dem;
    if (dem_path.empty()) {
      auto shipped = defaultTerrainPath();
      if (!shipped) fail(tool, kExitBadInput, shipped.error().describe());
      dem_path = *shipped;
    }
    auto dem = Dem::load(dem_path);
    if (!dem) fail(tool, kExitBadInput, "--dem " + dem.error().describe());
    auto terrain = Heightfield::build(*dem);
    if (!terrain) fail(tool, kExitBadInput, "--dem " + terrain.error().describe());
    for (FeedEntry& entry : feed->entries) entry.placeIn((*terrain)->frame());
  }

  dds::Entity participant = openParticipant(tool, o.domain);
  auto writer = openWriter<ObstacleUpdateData>(tool, participant);
  // The waitset only serves as an interruptible sleep: Ctrl-C triggers it.
  auto sleeper = openWaitLoop(tool, participant);
  stopOnSignals(sleeper.waitsetHandle());
  if (o.readers > 0) {
    Status matched = writer.waitForReaders(static_cast<uint32_t>(o.readers), o.wait_s);
    if (!matched) fail(tool, kExitServiceUnavailable, matched.error().message);
  }

  std::size_t published = 0;
  bool stopped = false;
  const auto started = std::chrono::steady_clock::now();
  auto at = [&](double s) {
    return std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(s));
  };
  do {
    const auto pass_start = std::chrono::steady_clock::now();
    for (const FeedEntry& entry : feed->entries) {
      // With --rate the updates go out evenly, one every 1/rate s, counted from the start.
      const auto due = o.rate > 0.0 ? started + at(static_cast<double>(published) / o.rate)
                                    : pass_start + at(entry.t_s / o.speed);
      if (o.duration_s > 0.0 && due - started >= at(o.duration_s)) {
        stopped = true;
        break;
      }
      for (;;) {
        const double wait_s = std::chrono::duration<double>(due - std::chrono::steady_clock::now()).count();
        if (wait_s <= 0.0) break;
        auto outcome = sleeper.runOnce(wait_s);
        if (!outcome) fail(tool, kExitServiceUnavailable, outcome.error().describe());
        if (*outcome == dds::WaitLoop::Outcome::kStopped) {
          stopped = true;
          break;
        }
      }
      if (stopped) break;
      Status s = writer.write(entry.stamped(utcNowNs()));
      if (!s) fail(tool, kExitServiceUnavailable, s.error().describe());
      ++published;
    }
  } while (o.loop && !stopped);
  // Reliable delivery of the last updates before the writer goes away.
  Status acked = writer.waitForAcks(5.0);
  if (!acked) std::cerr << "skyroute replay: " << acked.error().describe() << std::endl;
  std::cout << "published " << published << " obstacle updates from " << o.input << std::endl;
}

}  // namespace

void addReplayCommand(CLI::App& app) {
  auto options = std::make_shared<ReplayOptions>();
  CLI::App* cmd = app.add_subcommand("replay", "Publish a recorded obstacle feed with its original timing");
  cmd->footer(helpFooter({"skyroute replay data/feeds/default_terrain_table1.jsonl --domain 0 --readers 1",
                          "skyroute replay feed.jsonl --domain 0 --speed 2 --loop --dem white_mountains.tif",
                          "skyroute replay feed.jsonl --domain 0 --rate 10000 --loop --duration 60"}));
  cmd->add_option("FILE", options->input, "Feed file (JSON lines, docs/obstacle_feed.md)")->required();
  cmd->add_option("--domain", options->domain, "DDS domain id")->capture_default_str();
  addSecurityOption(*cmd);
  cmd->add_option("--dem", options->dem,
                  "The daemon's DEM: its frame places the feed's position_deg obstacles (default: the embedded terrain)");
  cmd->add_option("--speed", options->speed, "Time scale: 2 plays twice as fast")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_flag("--loop", options->loop, "Start again at the end, until Ctrl-C");
  cmd->add_option("--readers", options->readers, "Wait for this many subscribers before starting")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--wait", options->wait_s, "Seconds to wait for --readers")->capture_default_str();
  cmd->add_option("--rate", options->rate,
                  "Publish this many updates per second, evenly, ignoring the feed's t_s (a flood test)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--duration", options->duration_s, "Stop after this many seconds (with --loop: a timed run)")
      ->check(CLI::NonNegativeNumber);
  cmd->callback([options] { runReplay(*options); });
}

}  // namespace skyroute::cli
