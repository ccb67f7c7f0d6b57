// Not implemented yet: registers nothing, so `skyroute --help` does not list it.
#include <CLI/CLI.hpp>

#include "service/cli/commands.hpp"

namespace skyroute::cli {

void addGridPathCommand(CLI::App& /*grid*/) {}

}  // namespace skyroute::cli
