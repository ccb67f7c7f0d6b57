// The DDS tools of `skyroute`, each in its own file; main.cpp registers them next to the others.
#pragma once

namespace CLI {
class App;
}

namespace skyroute::cli {

void addGcsCommand(CLI::App& app);      // gcs: ground-station view and export      (gcs_command.cpp)
void addRequestCommand(CLI::App& app);  // request: publish a mission, await status (request_command.cpp)
void addRecordCommand(CLI::App& app);   // record: obstacle updates to a feed file   (record_command.cpp)
void addReplayCommand(CLI::App& app);   // replay: a feed file with its timing       (replay_command.cpp)
void addPx4Command(CLI::App& app);      // px4: offboard setpoints for PX4           (px4_command.cpp)

}  // namespace skyroute::cli
