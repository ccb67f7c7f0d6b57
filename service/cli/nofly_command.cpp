// skyroute nofly: publishes the no-fly zones of a GeoJSON file (docs/nofly.md) to the daemons on a
// DDS domain, or lifts zones by id. The topic is transient-local: a daemon that starts while this
// command is up still gets every zone, so the command stays up (--hold) to serve late joiners; once
// it exits, daemons keep the zones they have, and new daemons no longer learn them.
#include <chrono>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "service/cli/dds_cli_common.hpp"
#include "service/cli/dds_commands.hpp"
#include "service/cli/nofly_option.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/number_text.hpp"

namespace skyroute::cli {
namespace {

const std::string kTool = "nofly";

struct NoFlyOptions {
  int domain = 0;
  std::string file;
  std::vector<std::string> lift;
  double hold_s = 0.0;  // 0 = until Ctrl-C
  double wait_s = 10.0;
};

void runNoFly(const NoFlyOptions& o) {
  if (o.file.empty() && o.lift.empty()) fail(kTool, kExitUsage, "give a GeoJSON FILE to publish, or --lift ID");
  std::vector<NoFlyZoneData> zones = o.file.empty() ? std::vector<NoFlyZoneData>{} : loadNoFlyZoneData(kTool, "FILE", o.file);
  for (const std::string& id : o.lift) {
    NoFlyZoneData lifted;
    lifted.zone_id = id;
    lifted.remove = true;
    zones.push_back(lifted);
  }
  dds::Entity participant = openParticipant(kTool, o.domain);
  auto writer = dds::Writer<NoFlyZoneData>::create(participant.get());
  if (!writer) fail(kTool, kExitServiceUnavailable, writer.error().describe());
  auto loop = dds::WaitLoop::create(participant.get());
  if (!loop) fail(kTool, kExitServiceUnavailable, loop.error().describe());
  stopOnSignals(loop->waitsetHandle());
  for (const NoFlyZoneData& zone : zones) {
    if (Status written = writer->write(zone); !written) fail(kTool, kExitServiceUnavailable, written.error().describe());
    std::cout << (zone.remove ? "lifted zone " : "published zone ") << zone.zone_id << std::endl;
  }
  // Readers present now get the zones at once; wait for their acknowledgements when there are any.
  if (writer->waitForReaders(1, o.wait_s).ok()) (void)writer->waitForAcks(o.wait_s);
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    const double held_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o.hold_s > 0.0 && held_s >= o.hold_s) break;
    auto outcome = loop->runOnce(o.hold_s > 0.0 ? o.hold_s - held_s : 3600.0);
    if (!outcome) fail(kTool, kExitServiceUnavailable, outcome.error().describe());
    if (*outcome == dds::WaitLoop::Outcome::kStopped) break;
  }
}

}  // namespace

void addNoFlyCommand(CLI::App& app) {
  auto o = std::make_shared<NoFlyOptions>();
  CLI::App* cmd = app.add_subcommand("nofly", "Publish no-fly zones from a GeoJSON file to the daemons (or lift them)");
  cmd->add_option("FILE", o->file, "GeoJSON no-fly zones (docs/nofly.md); each zone's id is its name");
  cmd->add_option("--domain", o->domain, "DDS domain id")->capture_default_str();
  addSecurityOption(*cmd);
  cmd->add_option("--lift", o->lift, "Lift the zone with this id (repeatable)");
  cmd->add_option("--hold", o->hold_s,
                  "Stay up this many seconds serving the zones to daemons that start later (0 = until Ctrl-C)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--wait", o->wait_s, "Wait this long for a daemon to acknowledge the zones, seconds")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->footer("Example: skyroute nofly zones.geojson --domain 7 --hold 600\n" + std::string(kExitCodeTable));
  cmd->callback([o] { runNoFly(*o); });
}

}  // namespace skyroute::cli
