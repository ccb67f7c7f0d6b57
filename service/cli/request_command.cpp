// skyroute request: publishes one mission and prints the statuses the service sends for it;
// exit 0 only when the plan succeeded (1 failed or cancelled, 2 a bad option, 3 a bad --file,
// 4 no service or no answer in time, 5 the service that accepted the request was lost). The
// mission is checked here first, as the service checks it, so a bad value is named as the user
// wrote it.
// Before publishing it waits until every live planning service (the daemons behind the heartbeat
// writers it discovers) reads requests and writes statuses, so which daemon plans it is never a
// matter of discovery timing. It takes only the statuses addressed to its own writer (another
// client may use the same request id), and watches the heartbeat of the daemon that accepted
// the request: silence for 2.5 heartbeat periods means that daemon is gone.
#include <algorithm>
#include <chrono>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <set>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "service/cli/dds_cli_common.hpp"
#include "service/cli/dds_commands.hpp"
#include "service/cli/height_ref_option.hpp"
#include "service/cli/mission_args.hpp"
#include "service/cli/progress.hpp"
#include "service/dds/service_instance.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/number_text.hpp"

namespace skyroute::cli {

namespace {

struct RequestOptions {
  int domain = 0;
  std::string vehicle, request_id, planner;
  MissionPointArgs mission;  // --file, --from/--via/--to, --fixed-order and the vehicle limits
  double wait_s = 30.0;
  bool progress = false;  // --progress: the waiting on stderr even when it is not a terminal
  HeightRefArgs height_ref;
};

constexpr double kProgressEveryS = 2.0;  // how often a terminal hears what the request waits for

// The mission: the file's with the options on top, ids filled in, checked here as the service
// would check it, so a bad value is named as the user wrote it (the option, or the file's field,
// or a default) before anything is sent.
MissionRequestData buildMission(const RequestOptions& o) {
  const std::string tool = "request";
  MissionRequestData m = missionInAmsl(tool, o.height_ref, o.mission.mission_file, buildMissionRequest(tool, o.mission));
  if (!o.vehicle.empty()) m.vehicle_id = o.vehicle;
  if (m.vehicle_id.empty()) fail(tool, kExitUsage, "--vehicle is required (or vehicle_id in --file)");
  if (!o.planner.empty()) m.planner = o.planner;
  if (!o.request_id.empty()) m.request_id = o.request_id;
  if (m.request_id.empty())
    m.request_id = m.vehicle_id + "-" + std::to_string(::getpid()) + "-" + std::to_string(utcNowNs() / 1000000);
  if (auto problem = validateMissionRequest(m)) {
    problem->stage = PlanStage::kValidate;
    failPlanError(tool, o.mission, *problem);
  }
  return m;
}

using Clock = std::chrono::steady_clock;

// A service is lost when it has been silent this many heartbeat periods (one lost best-effort
// heartbeat is tolerated), and never sooner than kMinLostAfterS.
constexpr double kLostAfterPeriods = 2.5;
constexpr double kMinLostAfterS = 0.5;

struct Heard {
  Clock::time_point at;
  double period_s = 1.0;
};

// The DDS endpoints of one request: the status reader exists before the request is written, so
// no reply can be missed.
struct RequestEndpoints {
  dds::Reader<PlanStatusData> statuses;
  dds::Reader<ServiceStatusData> heartbeats;
  dds::Writer<MissionRequestData> writer;
};

// The live planning services: instance ids, and the heartbeat period each announced.
struct LiveServices {
  std::set<std::string> instances;
  std::map<std::string, double> periods_s;
};

// Waits until every live service reads our requests and writes statuses to us (see the top).
LiveServices waitForEveryService(const std::string& tool, const RequestOptions& o, const dds::Entity& participant,
                                 const RequestEndpoints& e, const std::function<double()>& left_s,
                                 const TerminalProgress& progress) {
  // Every live service, from discovery: the daemons among the participants (known first), and
  // the heartbeat writers they serve by. Each must read our requests and write statuses to us
  // before the request goes out; the counts must then hold for a moment (another daemon's
  // participant may be a little behind the first one's endpoints).
  auto daemons = dds::createParticipantReader(participant.get());
  if (!daemons) fail(tool, kExitServiceUnavailable, daemons.error().describe());
  auto discovery = openWaitLoop(tool, participant);
  for (auto [entity, mask] : {std::pair{e.writer.handle(), DDS_PUBLICATION_MATCHED_STATUS},
                              std::pair{e.statuses.handle(), DDS_SUBSCRIPTION_MATCHED_STATUS},
                              std::pair{e.heartbeats.handle(), DDS_SUBSCRIPTION_MATCHED_STATUS},
                              std::pair{daemons->get(), DDS_DATA_AVAILABLE_STATUS}}) {
    if (Status watched = discovery.addStatus(entity, mask, [] {}); !watched)
      fail(tool, kExitServiceUnavailable, watched.error().describe());
  }
  stopOnSignals(discovery.waitsetHandle());
  constexpr double kSettleS = 0.1;
  LiveServices live;
  bool settled = false;  // the counts held since settled_since
  Clock::time_point settled_since;
  for (;;) {
    std::set<std::string> reached;
    for (const dds::ServiceInstance& s : dds::matchedInstances(e.heartbeats.handle())) {
      reached.insert(s.instance_id);
      live.periods_s[s.instance_id] = s.heartbeat_period_s;
    }
    live.instances = reached;
    for (const dds::ServiceInstance& s : dds::discoveredInstances(daemons->get())) live.instances.insert(s.instance_id);
    const auto n = static_cast<uint32_t>(live.instances.size());
    const bool all = n > 0 && reached.size() == live.instances.size() && dds::matchedReaders(e.writer.handle()) >= n &&
                     dds::matchedWriters(e.statuses.handle()) >= n;
    if (!all) {
      settled = false;
    } else if (!settled) {
      settled = true;
      settled_since = Clock::now();
    } else if (std::chrono::duration<double>(Clock::now() - settled_since).count() >= kSettleS) {
      return live;
    }
    progress.every(kProgressEveryS, [&] {
      return "waiting on domain " + std::to_string(o.domain) + ": " + std::to_string(n) + " planning service" +
             (n == 1 ? "" : "s") + " discovered, " + std::to_string(reached.size()) + " with a heartbeat; " +
             numberText(std::max(0.0, left_s()), 3) + " s left of --wait";
    });
    if (left_s() <= 0.0) {
      if (n == 0)
        fail(tool, kExitServiceUnavailable, "no planning service is listening on domain " + std::to_string(o.domain) +
                                       " (waited " + numberText(o.wait_s) + " s)");
      fail(tool, kExitServiceUnavailable, std::to_string(n) + " planning services are live on domain " + std::to_string(o.domain) +
                                     " but not all of them matched this client within " + numberText(o.wait_s) + " s");
    }
    const double wait_s = settled ? 0.02 : std::max(0.01, left_s());
    auto outcome = discovery.runOnce(std::min(wait_s, std::max(0.01, left_s())));
    if (!outcome) fail(tool, kExitServiceUnavailable, outcome.error().describe());
    if (*outcome == dds::WaitLoop::Outcome::kStopped) fail(tool, kExitPlanningFailed, "interrupted before the request was sent");
  }
}

// Why a service that accepted the request is lost ("" while every one is alive): heartbeats on
// time, and (before its first heartbeat reached us) still discovered.
// A primary and its hot standby serve one service_id: only the live one of the two is heard
// (heartbeats and statuses are owned, docs/dds.md), and a lost primary is not a lost service
// while its standby's heartbeat is on time.
std::string lostService(const std::set<std::string>& accepted_by, const std::map<std::string, Heard>& heard,
                        const dds::Reader<ServiceStatusData>& heartbeats, std::string* lost_instance) {
  std::set<std::string> discovered;
  std::map<std::string, std::string> service_of;  // instance id -> service id
  for (const dds::ServiceInstance& s : dds::matchedInstances(heartbeats.handle())) {
    discovered.insert(s.instance_id);
    service_of[s.instance_id] = s.service_id;
  }
  const auto on_time = [&](const std::string& instance, double* silent_s = nullptr, double* period_s = nullptr) {
    const auto h = heard.find(instance);
    if (h == heard.end()) return false;
    const double silent = std::chrono::duration<double>(Clock::now() - h->second.at).count();
    if (silent_s) *silent_s = silent;
    if (period_s) *period_s = h->second.period_s;
    return silent <= std::max(kMinLostAfterS, kLostAfterPeriods * h->second.period_s);
  };
  const auto standby_serves = [&](const std::string& instance) {
    const auto service = service_of.find(instance);
    if (service == service_of.end()) return false;
    for (const auto& [other, other_service] : service_of) {
      if (other != instance && other_service == service->second && on_time(other)) return true;
    }
    return false;
  };
  for (const std::string& instance : accepted_by) {
    *lost_instance = instance;
    double silent_s = 0.0, period_s = 0.0;
    if (heard.count(instance) > 0) {
      if (!on_time(instance, &silent_s, &period_s) && !standby_serves(instance)) {
        return "sent no heartbeat for " + numberText(silent_s, 3) + " s (its period is " + numberText(period_s) +
               " s)";
      }
    } else if (discovered.count(instance) == 0) {
      return "is no longer discovered on the domain";
    }
  }
  return "";
}

void runRequest(const RequestOptions& o) {
  const std::string tool = "request";
  const MissionRequestData mission = buildMission(o);
  dds::Entity participant = openParticipant(tool, o.domain);
  RequestEndpoints endpoints{openReader<PlanStatusData>(tool, participant), openReader<ServiceStatusData>(tool, participant),
                             openWriter<MissionRequestData>(tool, participant)};
  auto loop = openWaitLoop(tool, participant);
  const std::string me = dds::entityGuid(endpoints.writer.handle());
  const auto start = Clock::now();
  const std::function<double()> left_s = [&] {
    return o.wait_s - std::chrono::duration<double>(Clock::now() - start).count();
  };
  const TerminalProgress progress(o.progress);
  LiveServices live = waitForEveryService(tool, o, participant, endpoints, left_s, progress);

  stopOnSignals(loop.waitsetHandle());
  Status written = endpoints.writer.write(mission);
  if (!written) fail(tool, kExitServiceUnavailable, written.error().describe());
  std::cout << "sent request=" << mission.request_id << " vehicle=" << mission.vehicle_id
            << " points=" << mission.points.size() << " services=" << live.instances.size() << std::endl;

  std::map<std::string, Heard> heard;           // instance id -> its last heartbeat
  std::set<std::string> accepted_by;            // instances answering this request
  std::optional<PlanStatusData> final_status;
  std::string last_state = "sent";  // the latest status of this request, for the progress lines
  Status added = loop.add<PlanStatusData>(
      endpoints.statuses,
      [&](PlanStatusData&& s) {
        if (s.request_id != mission.request_id) return;
        if (!s.requester.empty() && s.requester != me) return;  // another client's request with this id
        std::cout << describe(s) << std::endl;
        last_state = std::string(to_string(s.state));
        // Until its next heartbeat, a service is timed from its answer, with the period it announced.
        if (!s.service_instance.empty() && accepted_by.insert(s.service_instance).second &&
            heard.count(s.service_instance) == 0 && live.periods_s.count(s.service_instance) > 0) {
          heard[s.service_instance] = Heard{Clock::now(), live.periods_s[s.service_instance]};
        }
        if (isTerminal(s.state)) {
          final_status = std::move(s);
          loop.stop();
        }
      },
      [](const Error& e) { std::cerr << "skyroute request: skipped a bad status: " << e.describe() << std::endl; });
  if (!added) fail(tool, kExitServiceUnavailable, added.error().describe());
  added = loop.add<ServiceStatusData>(
      endpoints.heartbeats,
      [&](ServiceStatusData&& s) {
        if (!s.instance_id.empty()) heard[s.instance_id] = Heard{Clock::now(), s.heartbeat_period_s};
      },
      [](const Error&) {});
  if (!added) fail(tool, kExitServiceUnavailable, added.error().describe());
  while (!final_status && left_s() > 0.0) {
    auto outcome = loop.runOnce(std::min(0.1, std::max(0.01, left_s())));
    if (!outcome) fail(tool, kExitServiceUnavailable, outcome.error().describe());
    if (*outcome == dds::WaitLoop::Outcome::kStopped) break;
    progress.every(kProgressEveryS, [&] {
      return "request " + mission.request_id + ": " + last_state + "; " + numberText(std::max(0.0, left_s()), 3) +
             " s left of --wait";
    });
    if (accepted_by.empty()) continue;
    std::string instance;
    if (const std::string why = lostService(accepted_by, heard, endpoints.heartbeats, &instance); !why.empty()) {
      fail(tool, kExitServiceLost, "service lost: the planning service (instance " + instance +
                                       ") that accepted request " + mission.request_id + " " + why +
                                       "; the request is lost");
    }
  }
  if (!final_status)
    fail(tool, kExitServiceUnavailable, "no final status for request " + mission.request_id + " within " + numberText(o.wait_s) + " s");
  if (final_status->state != PlanState::kSucceeded)
    fail(tool, kExitPlanningFailed, "request " + mission.request_id + " " + std::string(to_string(final_status->state)) + ": " +
                                 std::string(to_string(final_status->error_code)) +
                                 (final_status->message.empty() ? "" : " (" + final_status->message + ")"));
}

}  // namespace

void addRequestCommand(CLI::App& app) {
  auto options = std::make_shared<RequestOptions>();
  options->mission.file_option = "--file";
  MissionPointArgs& mission = options->mission;
  CLI::App* cmd = app.add_subcommand("request", "Publish a mission to the planning service and print its status");
  cmd->footer(helpFooter({"skyroute request --domain 0 --file data/missions/demo_mission.json --wait 120",
                          "skyroute request --vehicle uav-1 --from 46.90,15.03,1100 --via '46.95,15.06,1150' "
                          "--to 46.97,15.12,1100 --max-speed-mps 25"}));
  cmd->add_option("--domain", options->domain, "DDS domain id")->capture_default_str();
  addSecurityOption(*cmd);
  cmd->add_option("--vehicle", options->vehicle, "Vehicle id (default: the file's vehicle_id)");
  cmd->add_option("--file", mission.mission_file, "Mission JSON (docs/dds.md); the options below override it");
  cmd->add_option("--from", mission.from, "Start LAT,LON,ALT (degrees, degrees, metres AMSL)");
  cmd->add_option("--to", mission.to, "Goal LAT,LON,ALT");
  cmd->add_option("--via", mission.via,
                  "Mission points LAT,LON,ALT (repeatable, or ';'-separated); the service orders them unless "
                  "--fixed-order")
      ->delimiter(';');
  // The names before --from/--via/--to, kept for one release (hidden).
  cmd->add_option("--begin", mission.from, "old name of --from")->group("");
  cmd->add_option("--points", mission.via, "old name of --via")->group("")->delimiter(';');
  cmd->add_option("--end", mission.to, "old name of --to")->group("");
  cmd->add_flag("--fixed-order", mission.fixed_order, "Visit the points in the given order");
  cmd->add_option("--request-id", options->request_id, "Request id (default: the file's, else vehicle-pid-milliseconds)");
  cmd->add_option("--planner", options->planner, "Planner name (default: the file's, else the service's)");
  addFlightBandOptions(*cmd, mission.limits);
  addVehicleDynamicsOptions(*cmd, mission.limits);
  addHeightRefOption(*cmd, options->height_ref);
  cmd->add_flag("--progress", options->progress,
                "Say every 2 s on stderr what the request waits for, even when stderr is not a terminal");
  cmd->add_option("--wait", options->wait_s, "Seconds to wait for the service and its answer")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->callback([options] { runRequest(*options); });
}

}  // namespace skyroute::cli
