// The DDS tools of `skyroute`, each in its own file; main.cpp registers them next to the others.
#pragma once

#include <string>

namespace CLI {
class App;
class Option;
}

namespace skyroute {
struct FleetRequestData;
}

namespace skyroute::cli {

void addGcsCommand(CLI::App& app);      // gcs: ground-station view and export      (gcs_command.cpp)
void addRequestCommand(CLI::App& app);  // request: publish a mission, await status (request_command.cpp)
void addRecordCommand(CLI::App& app);   // record: obstacle updates to a feed file   (record_command.cpp)
void addReplayCommand(CLI::App& app);   // replay: a feed file with its timing       (replay_command.cpp)
void addPx4Command(CLI::App& app);      // px4: offboard setpoints for PX4           (px4_command.cpp)
void addCancelCommand(CLI::App& app);   // cancel: a vehicle's mission or a request   (cancel_command.cpp)
void addStatusCommand(CLI::App& app);   // status: live daemons from their heartbeats (status_command.cpp)
void addNoFlyCommand(CLI::App& app);    // nofly: publish or lift no-fly zones        (nofly_command.cpp)

// `--security DIR` on a DDS subcommand: the participant it opens uses that identity folder
// (scripts/make-pki.sh; DIR/station to send requests). One command runs per process, so the
// folder is kept for that participant (dds_cli_common.cpp).
CLI::Option* addSecurityOption(CLI::App& command);

// fleet --domain: publishes the fleet request, prints its statuses and, on success, the outcome
// and each vehicle's trajectory (written to `out` when given); fails with the exit-code table's
// codes (fleet_dds_command.cpp).
void requestFleetOverDds(const std::string& tool, const FleetRequestData& request, int domain, double wait_s,
                         const std::string& out);

}  // namespace skyroute::cli
