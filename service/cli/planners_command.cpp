// skyroute planners: the route planners a mission may name, one line each, from the registry.
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "service/cli/commands.hpp"
#include "service/cli/cli_parse.hpp"
#include "service/planner_registry.hpp"

namespace skyroute::cli {

void addPlannersCommand(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand(
      "planners", "List the route planners a mission, --planner or planning.default_planner may name");
  cmd->footer(helpFooter({"skyroute planners"}));
  cmd->callback([] {
    for (const RoutePlannerInfo& p : routePlanners()) {
      std::string keys;
      for (std::string_view key : p.config_keys) keys += (keys.empty() ? "" : ", ") + std::string(key);
      std::printf("%-14s %s%s; tuned by %s\n", std::string(p.name).c_str(), std::string(p.summary).c_str(),
                  p.name == kDefaultRoutePlanner ? " (the default)" : "", keys.c_str());
    }
  });
}

}  // namespace skyroute::cli
