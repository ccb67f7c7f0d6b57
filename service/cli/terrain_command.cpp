#include <CLI/CLI.hpp>

#include "service/cli/commands.hpp"

namespace skyroute::cli {

void addTerrainCommands(CLI::App& /*app*/) {}

}  // namespace skyroute::cli
