// skyroute status: the planning services live on a domain, from their heartbeats (ServiceStatus):
// each daemon's service id, instance, host and pid, uptime, queue length, active vehicles,
// replans, obstacles and terrain. It listens until every daemon discovered on the domain has sent
// a heartbeat (participant discovery names them before their first heartbeat), or --wait.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "service/cli/dds_cli_common.hpp"
#include "service/cli/dds_commands.hpp"
#include "service/dds/service_instance.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/number_text.hpp"

namespace skyroute::cli {

namespace {

const std::string kTool = "status";

struct StatusOptions {
  int domain = 0;
  double wait_s = 3.0;
  bool json = false;
};

struct LiveService {
  ServiceStatusData heartbeat;
  dds::ServiceInstance instance;  // host and pid, from discovery (empty when not discovered)
};

// A hot standby whose primary is heard: its heartbeats are owned by the primary's (docs/dds.md).
bool standbyOfHeard(const dds::ServiceInstance& instance, const std::map<std::string, LiveService>& heard) {
  if (instance.role != "standby") return false;
  return std::any_of(heard.begin(), heard.end(),
                     [&](const auto& h) { return h.second.heartbeat.service_id == instance.service_id; });
}

double uptimeS(const ServiceStatusData& s) { return static_cast<double>(s.stamp_utc_ns - s.started_utc_ns) * 1e-9; }

nlohmann::json toJson(const LiveService& l) {
  const ServiceStatusData& s = l.heartbeat;
  return {{"service_id", s.service_id},     {"instance_id", s.instance_id},  {"host", l.instance.host},
          {"pid", l.instance.pid},          {"uptime_s", uptimeS(s)},        {"queue_length", s.queue_length},
          {"vehicles", s.vehicles},         {"replans", s.replans},          {"obstacles", s.obstacles},
          {"terrain_loaded", s.terrain_loaded}, {"terrain", s.terrain_name}, {"version", s.service_version},
          {"heartbeat_period_s", s.heartbeat_period_s}, {"shard_group", l.instance.shard_group},
          {"audits", s.audits},             {"audit_failures", s.audit_failures}};
}

std::string describeLine(const LiveService& l) {
  const ServiceStatusData& s = l.heartbeat;
  char uptime[32];
  std::snprintf(uptime, sizeof uptime, "%.1f", uptimeS(s));
  return "service=" + s.service_id + " instance=" + s.instance_id +
         (l.instance.role.empty() || l.instance.host.empty() ? "" : " role=" + l.instance.role) +
         (l.instance.host.empty() ? "" : " host=" + l.instance.host + " pid=" + std::to_string(l.instance.pid)) +
         // The members of a shard group are the services that name the same group.
         (l.instance.shard_group.empty() ? "" : " shard_group=" + l.instance.shard_group) +
         " uptime_s=" + uptime + " queue=" + std::to_string(s.queue_length) + " vehicles=" + std::to_string(s.vehicles) +
         " replans=" + std::to_string(s.replans) + " obstacles=" + std::to_string(s.obstacles) +
         " audits=" + std::to_string(s.audits) + " audit_failures=" + std::to_string(s.audit_failures) +
         " terrain=" + (s.terrain_loaded ? s.terrain_name : std::string("(none)")) + " version=" + s.service_version;
}

void runStatus(const StatusOptions& o) {
  dds::Entity participant = openParticipant(kTool, o.domain);
  auto heartbeats = openReader<ServiceStatusData>(kTool, participant);
  auto daemons = dds::createParticipantReader(participant.get());
  if (!daemons) fail(kTool, kExitServiceUnavailable, daemons.error().describe());
  auto loop = openWaitLoop(kTool, participant);
  stopOnSignals(loop.waitsetHandle());

  std::map<std::string, LiveService> heard;  // instance id -> its latest heartbeat
  Status added = loop.add<ServiceStatusData>(
      heartbeats,
      [&](ServiceStatusData&& s) {
        if (s.instance_id.empty()) return;
        const std::string id = s.instance_id;
        heard[id].heartbeat = std::move(s);
      },
      [](const Error& e) { std::cerr << "skyroute status: skipped a bad heartbeat: " << e.describe() << std::endl; });
  if (!added) fail(kTool, kExitServiceUnavailable, added.error().describe());

  // Discovery may name a daemon a moment after the first heartbeats: every one heard or
  // discovered must have been heard, and that must hold for a short while.
  constexpr double kSettleS = 0.3;
  const auto start = std::chrono::steady_clock::now();
  auto elapsed_s = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  std::map<std::string, dds::ServiceInstance> discovered;
  double all_heard_since_s = -1.0;  // < 0: not every daemon heard yet
  while (elapsed_s() < o.wait_s) {
    auto outcome = loop.runOnce(std::min(0.05, std::max(0.01, o.wait_s - elapsed_s())));
    if (!outcome) fail(kTool, kExitServiceUnavailable, outcome.error().describe());
    if (*outcome == dds::WaitLoop::Outcome::kStopped) break;
    for (dds::ServiceInstance& i : dds::discoveredInstances(daemons->get())) discovered[i.instance_id] = std::move(i);
    const bool all_heard = !discovered.empty() && std::all_of(discovered.begin(), discovered.end(), [&](const auto& d) {
      return heard.count(d.first) > 0 || standbyOfHeard(d.second, heard);
    });
    if (!all_heard) {
      all_heard_since_s = -1.0;
    } else if (all_heard_since_s < 0.0) {
      all_heard_since_s = elapsed_s();
    } else if (elapsed_s() - all_heard_since_s >= kSettleS) {
      break;
    }
  }
  for (auto& [id, live] : heard) {
    if (auto d = discovered.find(id); d != discovered.end()) live.instance = d->second;
  }
  for (const auto& [id, instance] : discovered) {
    if (heard.count(id) == 0 && standbyOfHeard(instance, heard)) {
      std::cout << "service=" << instance.service_id << " instance=" << id << " role=standby host=" << instance.host
                << " pid=" << instance.pid << " (hot standby: its heartbeats reach readers only while the primary is down)"
                << std::endl;
    } else if (heard.count(id) == 0) {
      std::cerr << "skyroute status: " << instance.service_id << " " << instance.describe()
                << " is discovered but sent no heartbeat within " << numberText(o.wait_s) << " s" << std::endl;
    }
  }
  if (heard.empty()) {
    fail(kTool, kExitServiceUnavailable,
         "no planning service heartbeat on domain " + std::to_string(o.domain) + " within " + numberText(o.wait_s) + " s");
  }
  if (o.json) {
    nlohmann::json services = nlohmann::json::array();
    for (const auto& [id, live] : heard) services.push_back(toJson(live));
    std::cout << nlohmann::json{{"domain", o.domain}, {"services", services}}.dump(2) << std::endl;
    return;
  }
  for (const auto& [id, live] : heard) std::cout << describeLine(live) << std::endl;
}

}  // namespace

void addStatusCommand(CLI::App& app) {
  auto options = std::make_shared<StatusOptions>();
  CLI::App* cmd = app.add_subcommand(
      "status", "The planning services live on a domain: queue length, active vehicles and uptime from their heartbeats");
  cmd->footer(helpFooter({"skyroute status --domain 0", "skyroute status --domain 0 --json"}));
  cmd->add_option("--domain", options->domain, "DDS domain id")->capture_default_str();
  addSecurityOption(*cmd);
  cmd->add_option("--wait", options->wait_s, "Seconds to listen for heartbeats at most")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--json", options->json, "Print one JSON object {domain, services: [...]}");
  cmd->callback([options] { runStatus(*options); });
}

}  // namespace skyroute::cli
