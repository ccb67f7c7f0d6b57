// Each subcommand family of `skyroute` lives in its own file and registers itself here.
// A command's callback reports failure by throwing CLI::RuntimeError(exit_code) after printing a
// message that names the offending file, field or point.
#pragma once

namespace CLI {
class App;
}

namespace skyroute::cli {

void addTerrainCommands(CLI::App& app);   // terrain info, terrain generate       (terrain_command.cpp)
void addGridSolveCommand(CLI::App& grid); // grid solve                           (grid_solve_command.cpp)
void addGridPathCommand(CLI::App& grid);  // grid path                            (grid_path_command.cpp)
void addMissionCommand(CLI::App& app);    // mission                              (mission_command.cpp)
void addPlanCommand(CLI::App& app);       // plan                                 (plan_command.cpp)
void addFleetCommand(CLI::App& app);      // fleet                                (fleet_command.cpp)
void addPlannersCommand(CLI::App& app);   // planners                             (planners_command.cpp)

}  // namespace skyroute::cli
