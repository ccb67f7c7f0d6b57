// skyroute nofly: publishes the no-fly zones of a GeoJSON file (docs/nofly.md) to the daemons on a
// DDS domain, or lifts zones by id, and exits once every daemon on the domain has them: each
// daemon discovered (its participant, or its heartbeat writer under DDS Security) reads the zone
// topic from this writer, and every reader has acknowledged what was written. The topic is
// transient-local: with --hold S the command stays up S seconds more (inf: until Ctrl-C), serving
// daemons that start later; once it exits, daemons keep the zones they have, and new daemons no
// longer learn them.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "service/cli/cli_parse.hpp"
#include "service/cli/dds_cli_common.hpp"
#include "service/cli/dds_commands.hpp"
#include "service/cli/nofly_option.hpp"
#include "service/dds/daemon_participants.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/number_text.hpp"

namespace skyroute::cli {
namespace {

const std::string kTool = "nofly";

struct NoFlyOptions {
  int domain = 0;
  std::string file;
  std::vector<std::string> lift;
  double hold_s = 0.0;  // after delivery; inf = until Ctrl-C
  double wait_s = 10.0;
};

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// How many daemons were reached, or why not all of them.
struct Delivery {
  std::size_t daemons = 0;  // discovered
  std::size_t reached = 0;  // of them, reading the zones from this writer
  bool acknowledged = false;
  bool interrupted = false;
};

// What tells this command which daemons are on the domain, and the loop that wakes on each change
// of it (and on SIGINT/SIGTERM). Declared in this order, the loop is destroyed first.
struct Discovery {
  dds::Entity daemons;                         // the DCPSParticipant reader
  dds::Reader<ServiceStatusData> heartbeats;   // the heartbeat writers (their USER_DATA under DDS Security)
  dds::WaitLoop loop;
};

Discovery openDiscovery(const dds::Entity& participant, const dds::Writer<NoFlyZoneData>& writer) {
  Discovery d{createdOrFail(kTool, dds::createParticipantReader(participant.get())),
              openReader<ServiceStatusData>(kTool, participant), openWaitLoop(kTool, participant)};
  for (auto [entity, mask] : {std::pair{writer.handle(), DDS_PUBLICATION_MATCHED_STATUS},
                              std::pair{d.heartbeats.handle(), DDS_SUBSCRIPTION_MATCHED_STATUS},
                              std::pair{d.daemons.get(), DDS_DATA_AVAILABLE_STATUS}}) {
    if (Status watched = d.loop.addStatus(entity, mask, [] {}); !watched)
      fail(kTool, kExitServiceUnavailable, watched.error().describe());
  }
  return d;
}

// Waits (at most wait_s) until every daemon discovered on the domain reads the zone topic from
// `writer`, the set holding for a moment (another daemon's participant may be a little behind the
// first one's endpoints), then until every reader acknowledged what was written.
Delivery deliver(Discovery& discovery, const dds::Writer<NoFlyZoneData>& writer, double wait_s) {
  constexpr double kSettleS = 0.1;
  const auto start = Clock::now();
  auto left_s = [&] { return wait_s - secondsSince(start); };
  Delivery d;
  bool settled = false;
  Clock::time_point settled_since;
  for (;;) {
    const std::vector<dds::DaemonParticipant> found =
        dds::daemonParticipants(discovery.daemons.get(), discovery.heartbeats.handle());
    d.daemons = found.size();
    d.reached = 0;
    for (const dds::DaemonParticipant& daemon : found) d.reached += dds::reachesParticipantOf(writer.handle(), daemon.guid);
    const bool all = d.daemons > 0 && d.reached == d.daemons;
    if (!all) {
      settled = false;
    } else if (!settled) {
      settled = true;
      settled_since = Clock::now();
    } else if (secondsSince(settled_since) >= kSettleS) {
      d.acknowledged = writer.waitForAcks(std::max(0.0, left_s())).ok();
      return d;
    }
    if (left_s() <= 0.0) return d;
    auto outcome = discovery.loop.runOnce(settled ? 0.02 : std::max(0.01, left_s()));
    if (!outcome) fail(kTool, kExitServiceUnavailable, outcome.error().describe());
    if (*outcome == dds::WaitLoop::Outcome::kStopped) {
      d.interrupted = true;
      return d;
    }
  }
}

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
  auto writer = openWriter<NoFlyZoneData>(kTool, participant);
  Discovery discovery = openDiscovery(participant, writer);
  stopOnSignals(discovery.loop.waitsetHandle());
  // Written at once: a daemon matched later gets them from the writer's history (transient-local).
  for (const NoFlyZoneData& zone : zones) {
    if (Status written = writer.write(zone); !written) fail(kTool, kExitServiceUnavailable, written.error().describe());
    std::cout << (zone.remove ? "lifted zone " : "published zone ") << zone.zone_id << std::endl;
  }
  const std::string on_domain = " on domain " + std::to_string(o.domain);
  const std::string what = o.file.empty() ? (o.lift.size() == 1 ? "the lift" : "the lifts") : "the zones";
  const bool hold = o.hold_s > 0.0;
  const Delivery d = deliver(discovery, writer, o.wait_s);
  if (d.interrupted) fail(kTool, kExitServiceUnavailable, "interrupted before every daemon" + on_domain + " had " + what);
  if (d.acknowledged) {
    std::cout << "acknowledged by " << d.daemons << (d.daemons == 1 ? " daemon" : " daemons") << on_domain << std::endl;
  } else {
    const std::string why =
        d.daemons == 0 ? "no planning service is listening" + on_domain
                       : std::to_string(d.reached) + " of the " + std::to_string(d.daemons) + " planning services" +
                             on_domain + " read " + what + (d.reached == d.daemons ? " but did not acknowledge" : "");
    if (!hold) fail(kTool, kExitServiceUnavailable, why + " within --wait " + numberText(o.wait_s) + " s");
    // Holding, the writer still serves the daemons that start (or match) later.
    std::cout << why << " yet; holding " << what << " for daemons that start later" << std::endl;
  }
  if (!hold) return;
  const auto start = Clock::now();
  for (;;) {
    const double left_s = o.hold_s - secondsSince(start);
    if (left_s <= 0.0) break;
    auto outcome = discovery.loop.runOnce(std::isfinite(left_s) ? left_s : 3600.0);
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
  cmd->add_option("--wait", o->wait_s,
                  "Wait at most this long for every daemon on the domain to read and acknowledge the zones, seconds "
                  "(none: exit 4, unless --hold)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--hold", o->hold_s,
                  "Then stay up this many seconds serving the zones to daemons that start later (inf: until Ctrl-C; "
                  "0: exit once delivered)")
      ->check(CLI::Validator(
          [](std::string& text) {
            // strtod reads "inf" too, which CLI::NonNegativeNumber refuses as out of range.
            char* end = nullptr;
            const double seconds = std::strtod(text.c_str(), &end);
            const bool number = end != text.c_str() && *end == '\0';
            return number && seconds >= 0.0 ? std::string() : "--hold must be 0 or more seconds, or inf";
          },
          "SECONDS|inf"))
      ->capture_default_str();
  cmd->footer(helpFooter({"skyroute nofly zones.geojson --domain 7", "skyroute nofly zones.geojson --domain 7 --hold 600",
                          "skyroute nofly --lift stadium --domain 7"}));
  cmd->callback([o] { runNoFly(*o); });
}

}  // namespace skyroute::cli
