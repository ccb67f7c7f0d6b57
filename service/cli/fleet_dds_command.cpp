// skyroute fleet --domain N: one fleet request to a running skyrouted. Publishes the FleetRequest,
// prints every FleetStatus of it and, on success, the outcome and one Trajectory per vehicle (the
// daemon publishes them before its final status; late ones are awaited within --wait).
#include <chrono>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "service/cli/dds_cli_common.hpp"
#include "service/cli/dds_commands.hpp"
#include "service/cli/fleet_common.hpp"
#include "service/dds/wait_loop.hpp"

namespace skyroute::cli {

namespace {

std::string describe(const FleetStatusData& s) {
  std::ostringstream out;
  out << "fleet status request=" << s.request_id << " state=" << to_string(s.state) << " error=" << to_string(s.error_code)
      << " planning_time_s=" << s.planning_time_s;
  if (!s.field.empty()) out << " field=" << s.field;
  if (!s.message.empty()) out << " message=\"" << s.message << "\"";
  return out.str();
}

// What arrives for one request: its statuses (the last terminal one kept) and each vehicle's
// trajectory.
struct FleetReplies {
  std::optional<FleetStatusData> final_status;
  std::map<std::string, TrajectoryData> trajectories;  // by vehicle

  bool complete(const FleetRequestData& request) const {
    if (!final_status) return false;
    if (final_status->state != PlanState::kSucceeded) return true;
    for (const std::string& vehicle : request.vehicle_ids) {
      if (!trajectories.count(vehicle)) return false;
    }
    return true;
  }
};

}  // namespace

void requestFleetOverDds(const std::string& tool, const FleetRequestData& request, int domain, double wait_s,
                         const std::string& out) {
  dds::Entity participant = openParticipant(tool, domain);
  // Both readers exist before the request is written, so no reply can be missed.
  auto statuses = openReader<FleetStatusData>(tool, participant);
  auto trajectories = openReader<TrajectoryData>(tool, participant);
  auto writer = openWriter<FleetRequestData>(tool, participant);
  auto loop = openWaitLoop(tool, participant);
  stopOnSignals(loop.waitsetHandle());

  const auto start = std::chrono::steady_clock::now();
  auto left_s = [&] { return wait_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const std::string on_domain = " on domain " + std::to_string(domain);
  if (!writer.waitForReaders(1, wait_s)) {
    fail(tool, kExitServiceUnavailable,
         "no planning service is listening for fleet requests" + on_domain + " (waited " + numberText(wait_s) + " s)");
  }
  // The service's writers must have matched our readers too, or its first replies could be lost.
  if (!statuses.waitForWriters(1, std::max(0.0, left_s())) || !trajectories.waitForWriters(1, std::max(0.0, left_s()))) {
    fail(tool, kExitServiceUnavailable, "the planning service has no fleet status or trajectory writer" + on_domain);
  }
  if (Status written = writer.write(request); !written) fail(tool, kExitServiceUnavailable, written.error().describe());
  std::cout << "sent fleet request=" << request.request_id << " vehicles=" << request.vehicle_ids.size()
            << " tasks=" << request.tasks.size() << std::endl;

  FleetReplies replies;
  auto on_bad = [&tool](const Error& e) { std::cerr << "skyroute " << tool << ": skipped a bad sample: " << e.describe() << std::endl; };
  Status added = loop.add<FleetStatusData>(
      statuses,
      [&](FleetStatusData&& s) {
        if (s.request_id != request.request_id) return;
        std::cout << describe(s) << std::endl;
        if (isTerminal(s.state)) replies.final_status = std::move(s);
        if (replies.complete(request)) loop.stop();
      },
      on_bad);
  if (added) {
    added = loop.add<TrajectoryData>(
        trajectories,
        [&](TrajectoryData&& t) {
          if (t.request_id != request.request_id) return;  // another request's, or an earlier plan's
          replies.trajectories[t.vehicle_id] = std::move(t);
          if (replies.complete(request)) loop.stop();
        },
        on_bad);
  }
  if (!added) fail(tool, kExitServiceUnavailable, added.error().describe());
  auto outcome = loop.run(std::max(0.01, left_s()));
  if (!outcome) fail(tool, kExitServiceUnavailable, outcome.error().describe());

  const std::string waited = " within " + numberText(wait_s) + " s";
  if (!replies.final_status) {
    fail(tool, kExitServiceUnavailable, "no final status for fleet request " + request.request_id + waited);
  }
  const FleetStatusData& status = *replies.final_status;
  if (status.state != PlanState::kSucceeded) {
    fail(tool, kExitPlanningFailed,
         "fleet request " + request.request_id + " " + std::string(to_string(status.state)) + ": " +
             std::string(to_string(status.error_code)) + (status.message.empty() ? "" : " (" + status.message + ")"));
  }
  std::vector<TrajectoryData> flown;  // request order
  for (const std::string& vehicle : request.vehicle_ids) {
    auto it = replies.trajectories.find(vehicle);
    if (it == replies.trajectories.end()) {
      fail(tool, kExitServiceUnavailable, "fleet request " + request.request_id + " succeeded but no trajectory of " +
                                              vehicle + " arrived" + waited);
    }
    std::cout << cli::describe(it->second) << std::endl;
    flown.push_back(it->second);
  }
  printFleetOutcome(request, status, flown);
  if (!out.empty()) writeFleetTrajectories(tool, out, flown);
}

}  // namespace skyroute::cli
