// Not implemented yet: registers nothing, so `skyroute --help` does not list it.
#include <CLI/CLI.hpp>

#include "service/cli/commands.hpp"

namespace skyroute::cli {

void addFleetCommand(CLI::App& /*app*/) {}

}  // namespace skyroute::cli
