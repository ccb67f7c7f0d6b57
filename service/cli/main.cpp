// skyroute: the command-line tool, with git-style subcommands.
#include <CLI/CLI.hpp>
#include <gdal.h>

#include "service/cli/commands.hpp"
#include "service/cli/dds_commands.hpp"
#include "service/cli/cli_common.hpp"

int main(int argc, char** argv) {
  GDALAllRegister();
  CLI::App app{"skyroute: terrain-aware 3D trajectory planning for UAVs"};
  app.set_version_flag("--version", std::string("skyroute ") + SKYROUTE_VERSION);
  app.require_subcommand(1);

  skyroute::cli::addTerrainCommands(app);
  CLI::App* grid = app.add_subcommand("grid", "Grid searches on Moving AI maps and terrain grid layers");
  grid->require_subcommand(1);
  grid->footer(skyroute::cli::helpFooter({"skyroute grid path --map room-32-32-4.map --from 1,1 --to 30,30 --algo theta"}));
  skyroute::cli::addGridSolveCommand(*grid);
  skyroute::cli::addGridPathCommand(*grid);
  skyroute::cli::addMissionCommand(app);
  skyroute::cli::addPlanCommand(app);
  skyroute::cli::addFleetCommand(app);
  skyroute::cli::addPlannersCommand(app);
  skyroute::cli::addGcsCommand(app);
  skyroute::cli::addRequestCommand(app);
  skyroute::cli::addRecordCommand(app);
  skyroute::cli::addReplayCommand(app);
  skyroute::cli::addPx4Command(app);
  skyroute::cli::addCancelCommand(app);
  skyroute::cli::addNoFlyCommand(app);
  skyroute::cli::addStatusCommand(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // A subcommand's failure carries its code from the one table; CLI11's own parse errors
    // (an unknown option, a value out of range) are usage errors; --help and --version succeed.
    const int code = app.exit(e);
    if (code == 0 || dynamic_cast<const CLI::RuntimeError*>(&e) != nullptr) return code;
    return skyroute::cli::kExitUsage;
  }
  return skyroute::cli::kExitOk;
}
