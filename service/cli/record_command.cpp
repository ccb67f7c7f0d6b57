// skyroute record: writes the obstacle updates it hears to a feed file (docs/obstacle_feed.md),
// t_s counted from the first update, until Ctrl-C, --timeout or --count.
#include <iostream>
#include <optional>

#include <CLI/CLI.hpp>

#include "service/cli/dds_cli_common.hpp"
#include "service/cli/dds_commands.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/obstacle_feed.hpp"

namespace skyroute::cli {

namespace {

struct RecordOptions {
  int domain = 0;
  std::string output;
  int count = 0;
  double timeout_s = 0.0;
};

void runRecord(const RecordOptions& o) {
  const std::string tool = "record";
  auto feed = ObstacleFeedWriter::open(o.output);
  if (!feed) fail(tool, kExitBadInput, feed.error().describe());
  dds::Entity participant = openParticipant(tool, o.domain);
  auto updates = openReader<ObstacleUpdateData>(tool, participant);
  auto loop = openWaitLoop(tool, participant);
  stopOnSignals(loop.waitsetHandle());

  std::optional<std::int64_t> first_ns;
  std::optional<Error> write_error;
  Status added = loop.add<ObstacleUpdateData>(
      updates,
      [&](ObstacleUpdateData&& u) {
        const std::int64_t now_ns = utcNowNs();
        if (!first_ns) first_ns = now_ns;
        const double t_s = static_cast<double>(now_ns - *first_ns) * 1e-9;
        Status s = feed->append(FeedEntry::fromUpdate(u, t_s, now_ns));
        if (!s) {
          write_error = s.error();
          loop.stop();
          return;
        }
        if (o.count > 0 && static_cast<int>(feed->entriesWritten()) >= o.count) loop.stop();
      },
      [](const Error& e) { std::cerr << "skyroute record: skipped a bad update: " << e.describe() << std::endl; });
  if (!added) fail(tool, kExitServiceUnavailable, added.error().describe());
  auto outcome = loop.run(o.timeout_s > 0 ? std::optional<double>(o.timeout_s) : std::nullopt);
  if (!outcome) fail(tool, kExitServiceUnavailable, outcome.error().describe());
  if (write_error) fail(tool, kExitUsage, write_error->describe());
  std::cout << "recorded " << feed->entriesWritten() << " obstacle updates to " << o.output << std::endl;
  if (o.count > 0 && static_cast<int>(feed->entriesWritten()) < o.count)
    fail(tool, kExitPlanningFailed, "heard " + std::to_string(feed->entriesWritten()) + " of " + std::to_string(o.count) + " updates");
}

}  // namespace

void addRecordCommand(CLI::App& app) {
  auto options = std::make_shared<RecordOptions>();
  CLI::App* cmd = app.add_subcommand("record", "Record the obstacle updates on a domain to a feed file");
  cmd->footer(helpFooter({"skyroute record out/feed.jsonl --domain 0 --timeout 600",
                          "skyroute record out/feed.jsonl --domain 0 --count 10"}));
  cmd->add_option("FILE", options->output, "Feed file to write (JSON lines)")->required();
  cmd->add_option("--domain", options->domain, "DDS domain id")->capture_default_str();
  addSecurityOption(*cmd);
  cmd->add_option("--count", options->count, "Stop after K updates (0 = no limit)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--timeout", options->timeout_s, "Stop after S seconds (0 = until Ctrl-C)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->callback([options] { runRecord(*options); });
}

}  // namespace skyroute::cli
