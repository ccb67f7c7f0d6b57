// skyroute request: publishes one mission and prints the statuses the service sends for it;
// exit 0 only when the plan succeeded (1 failed or cancelled, 2 bad input, 3 no answer in time).
#include <chrono>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "service/cli/dds_cli_common.hpp"
#include "service/cli/dds_commands.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/mission_json.hpp"

namespace skyroute::cli {

namespace {

struct RequestOptions {
  int domain = 0;
  std::string vehicle, begin, points, end, file, request_id, planner;
  bool fixed_order = false;
  double wait_s = 30.0;
};

MissionRequestData buildMission(const RequestOptions& o) {
  const std::string tool = "request";
  MissionRequestData m;
  if (!o.file.empty()) {
    std::ifstream in(o.file);
    if (!in) fail(tool, kExitBadInput, o.file + ": cannot open the mission file");
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_discarded()) fail(tool, kExitBadInput, o.file + ": not valid JSON");
    auto parsed = missionFromJson(j);
    if (!parsed) fail(tool, kExitBadInput, o.file + ": " + parsed.error().describe());
    m = std::move(*parsed);
  } else if (o.begin.empty() || o.end.empty()) {
    fail(tool, kExitUsage, "--begin and --end are required unless --file gives the mission");
  }
  auto point = [&](const std::string& text, const std::string& field) {
    auto p = parseGeoTriple(text, field);
    if (!p) fail(tool, kExitUsage, p.error().message);
    return *p;
  };
  if (!o.vehicle.empty()) m.vehicle_id = o.vehicle;
  if (m.vehicle_id.empty()) fail(tool, kExitUsage, "--vehicle is required (or vehicle_id in --file)");
  if (!o.begin.empty()) m.begin = point(o.begin, "--begin");
  if (!o.end.empty()) m.end = point(o.end, "--end");
  if (!o.points.empty()) {
    m.points.clear();
    std::istringstream in(o.points);
    std::string item;
    for (int i = 0; std::getline(in, item, ';'); ++i)
      if (item.find_first_not_of(" \t") != std::string::npos)
        m.points.push_back(point(item, "--points[" + std::to_string(i) + "]"));
  }
  if (!o.planner.empty()) m.planner = o.planner;
  if (o.fixed_order) m.fixed_order = true;
  if (!o.request_id.empty()) m.request_id = o.request_id;
  if (m.request_id.empty())
    m.request_id = m.vehicle_id + "-" + std::to_string(::getpid()) + "-" + std::to_string(utcNowNs() / 1000000);
  return m;
}

void runRequest(const RequestOptions& o) {
  const std::string tool = "request";
  const MissionRequestData mission = buildMission(o);
  dds::Entity participant = openParticipant(tool, o.domain);
  // The status reader exists before the request is written, so no reply can be missed.
  auto statuses = dds::Reader<PlanStatusData>::create(participant.get());
  if (!statuses) fail(tool, kExitServiceUnavailable, statuses.error().describe());
  auto writer = dds::Writer<MissionRequestData>::create(participant.get());
  if (!writer) fail(tool, kExitServiceUnavailable, writer.error().describe());
  auto loop = dds::WaitLoop::create(participant.get());
  if (!loop) fail(tool, kExitServiceUnavailable, loop.error().describe());
  stopOnSignals(loop->waitsetHandle());

  const auto start = std::chrono::steady_clock::now();
  auto left_s = [&] { return o.wait_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  Status matched = writer->waitForReaders(1, o.wait_s);
  if (!matched)
    fail(tool, kExitServiceUnavailable, "no planning service is listening on domain " + std::to_string(o.domain) + " (waited " +
                                   std::to_string(o.wait_s) + " s)");
  // The service's status writer must also have matched our reader, or its first reply could be lost.
  Status replies = statuses->waitForWriters(1, std::max(0.0, left_s()));
  if (!replies) fail(tool, kExitServiceUnavailable, "the planning service has no status writer on domain " + std::to_string(o.domain));
  Status written = writer->write(mission);
  if (!written) fail(tool, kExitServiceUnavailable, written.error().describe());
  std::cout << "sent request=" << mission.request_id << " vehicle=" << mission.vehicle_id
            << " points=" << mission.points.size() << std::endl;

  std::optional<PlanStatusData> final_status;
  Status added = loop->add<PlanStatusData>(
      *statuses,
      [&](PlanStatusData&& s) {
        if (s.request_id != mission.request_id) return;
        std::cout << describe(s) << std::endl;
        if (isTerminal(s.state)) {
          final_status = std::move(s);
          loop->stop();
        }
      },
      [](const Error& e) { std::cerr << "skyroute request: skipped a bad status: " << e.describe() << std::endl; });
  if (!added) fail(tool, kExitServiceUnavailable, added.error().describe());
  auto outcome = loop->run(std::max(0.01, left_s()));
  if (!outcome) fail(tool, kExitServiceUnavailable, outcome.error().describe());
  if (!final_status)
    fail(tool, kExitServiceUnavailable, "no final status for request " + mission.request_id + " within " + std::to_string(o.wait_s) + " s");
  if (final_status->state != PlanState::kSucceeded)
    fail(tool, kExitPlanningFailed, "request " + mission.request_id + " " + std::string(to_string(final_status->state)) + ": " +
                                 std::string(to_string(final_status->error_code)) +
                                 (final_status->message.empty() ? "" : " (" + final_status->message + ")"));
}

}  // namespace

void addRequestCommand(CLI::App& app) {
  auto options = std::make_shared<RequestOptions>();
  CLI::App* cmd = app.add_subcommand("request", "Publish a mission to the planning service and print its status");
  cmd->add_option("--domain", options->domain, "DDS domain id")->capture_default_str();
  cmd->add_option("--vehicle", options->vehicle, "Vehicle id");
  cmd->add_option("--begin", options->begin, "Start point LAT,LON,ALT (degrees, metres AMSL)");
  cmd->add_option("--points", options->points, "Mission points \"LAT,LON,ALT;LAT,LON,ALT;...\"");
  cmd->add_option("--end", options->end, "End point LAT,LON,ALT");
  cmd->add_option("--file", options->file, "Mission JSON (docs/dds.md); the options above override it");
  cmd->add_option("--request-id", options->request_id, "Request id (default: vehicle-pid-milliseconds)");
  cmd->add_option("--planner", options->planner, "Planner name (default: the service's)");
  cmd->add_flag("--fixed-order", options->fixed_order, "Visit the points in the given order");
  cmd->add_option("--wait", options->wait_s, "Seconds to wait for the service and its answer")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->callback([options] { runRequest(*options); });
}

}  // namespace skyroute::cli
