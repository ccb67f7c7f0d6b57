// skyroute cancel: stops a vehicle's mission, or one request, on a running skyrouted. Publishes a
// CancelRequest naming the vehicle, the request or both, and waits for the service's answer: the
// cancelled status of each request it stopped (exit 0), or the refusal addressed to this client
// when nothing matched (exit 1).
#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "service/cli/dds_cli_common.hpp"
#include "service/cli/dds_commands.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/number_text.hpp"

namespace skyroute::cli {

namespace {

const std::string kTool = "cancel";

struct CancelOptions {
  int domain = 0;
  std::string vehicle, request_id;
  double wait_s = 10.0;
};

// Whether a status answers this cancel: a request it stopped, or its refusal (addressed to us).
bool answers(const CancelRequestData& cancel, const PlanStatusData& s) {
  if (!cancel.vehicle_id.empty() && s.vehicle_id != cancel.vehicle_id) return false;
  if (!cancel.request_id.empty() && s.request_id != cancel.request_id) return false;
  return s.state == PlanState::kCancelled || (s.state == PlanState::kFailed && s.requester == cancel.requester);
}

void runCancel(const CancelOptions& o) {
  if (o.vehicle.empty() && o.request_id.empty()) fail(kTool, kExitUsage, "give --vehicle V, --request ID, or both");
  dds::Entity participant = openParticipant(kTool, o.domain);
  // The status reader exists before the cancel is written, so no answer can be missed.
  auto statuses = openReader<PlanStatusData>(kTool, participant);
  auto writer = openWriter<CancelRequestData>(kTool, participant);
  auto loop = openWaitLoop(kTool, participant);
  stopOnSignals(loop.waitsetHandle());

  const auto start = std::chrono::steady_clock::now();
  auto left_s = [&] { return o.wait_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const std::string on_domain = " on domain " + std::to_string(o.domain);
  if (!writer.waitForReaders(1, o.wait_s)) {
    fail(kTool, kExitServiceUnavailable,
         "no planning service is listening for cancels" + on_domain + " (waited " + numberText(o.wait_s) + " s)");
  }
  if (!statuses.waitForWriters(1, std::max(0.0, left_s()))) {
    fail(kTool, kExitServiceUnavailable, "the planning service has no status writer" + on_domain);
  }
  // The service holds its answer until its status writer has matched our reader (up to 2 s):
  // knowing its writer does not mean it knows our reader yet.
  const CancelRequestData cancel{o.request_id, o.vehicle, dds::entityGuid(writer.handle())};
  if (Status written = writer.write(cancel); !written) fail(kTool, kExitServiceUnavailable, written.error().describe());
  std::cout << "sent cancel" << (o.vehicle.empty() ? "" : " vehicle=" + o.vehicle)
            << (o.request_id.empty() ? "" : " request=" + o.request_id) << std::endl;

  // The service answers every request it stopped at once; a short grace after the first answer
  // collects the others (a vehicle may have a queued request beside its flying one).
  constexpr double kMoreAnswersS = 0.3;
  int cancelled = 0;
  std::optional<PlanStatusData> refused;
  Status added = loop.add<PlanStatusData>(
      statuses,
      [&](PlanStatusData&& s) {
        if (!answers(cancel, s)) return;
        std::cout << describe(s) << std::endl;
        if (s.state == PlanState::kCancelled) {
          ++cancelled;
        } else {
          refused = std::move(s);
        }
      },
      [](const Error& e) { std::cerr << "skyroute cancel: skipped a bad status: " << e.describe() << std::endl; });
  if (!added) fail(kTool, kExitServiceUnavailable, added.error().describe());
  std::optional<std::chrono::steady_clock::time_point> first_answer;
  while (left_s() > 0.0) {
    if (first_answer && std::chrono::duration<double>(std::chrono::steady_clock::now() - *first_answer).count() >= kMoreAnswersS) break;
    auto outcome = loop.runOnce(std::min(0.05, std::max(0.01, left_s())));
    if (!outcome) fail(kTool, kExitServiceUnavailable, outcome.error().describe());
    if (*outcome == dds::WaitLoop::Outcome::kStopped) break;
    if (!first_answer && (cancelled > 0 || refused)) first_answer = std::chrono::steady_clock::now();
  }
  if (cancelled > 0) {
    std::cout << "cancelled " << cancelled << (cancelled == 1 ? " request" : " requests") << std::endl;
    return;
  }
  if (refused) fail(kTool, kExitPlanningFailed, refused->message);
  fail(kTool, kExitServiceUnavailable, "no answer to the cancel within " + numberText(o.wait_s) + " s");
}

}  // namespace

void addCancelCommand(CLI::App& app) {
  auto options = std::make_shared<CancelOptions>();
  CLI::App* cmd = app.add_subcommand("cancel", "Cancel a vehicle's mission or one request on a running skyrouted");
  cmd->footer(helpFooter({"skyroute cancel --domain 0 --vehicle uav-1", "skyroute cancel --domain 0 --request demo-1"}));
  cmd->add_option("--domain", options->domain, "DDS domain id")->capture_default_str();
  addSecurityOption(*cmd);
  cmd->add_option("--vehicle", options->vehicle, "Vehicle whose requests and flight to cancel");
  cmd->add_option("--request", options->request_id, "Request to cancel (with --vehicle: only that vehicle's)");
  cmd->add_option("--wait", options->wait_s, "Seconds to wait for the service and its answer")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->callback([options] { runCancel(*options); });
}

}  // namespace skyroute::cli
