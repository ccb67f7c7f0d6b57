// The planner registry as users meet it: `skyroute planners` lists every registered planner once,
// and a name the registry does not know is refused with the known names, on the command line, in a
// mission file and in the configuration.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "service/planner_registry.hpp"
#include "tests/cli_run.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

using testing::runCli;

TEST(PlannersCli, ListsEveryRegisteredPlannerOnALineOfItsOwn) {
  const auto out = runCli("planners");
  ASSERT_EQ(out.exit_code, 0) << out.text;
  std::istringstream lines(out.text);
  std::string line;
  std::size_t count = 0;
  while (std::getline(lines, line)) {
    ASSERT_LT(count, routePlanners().size()) << "more lines than planners: " << line;
    const RoutePlannerInfo& p = routePlanners()[count];
    EXPECT_EQ(line.rfind(std::string(p.name) + " ", 0), 0u) << line;
    ++count;
  }
  EXPECT_EQ(count, routePlanners().size());
}

TEST(PlannersCli, UnknownNamesAreRefusedWithTheKnownOnes) {
  const std::string known = routePlannerNames();
  auto out = runCli("plan --from 46.90,15.03,1100 --to 46.97,15.12,1100 --planner warp-drive");
  EXPECT_EQ(out.exit_code, 2) << out.text;
  EXPECT_NE(out.text.find("--planner"), std::string::npos) << out.text;
  EXPECT_NE(out.text.find(known), std::string::npos) << out.text;

  const auto dir = std::filesystem::path(::testing::TempDir());
  const std::string config = (dir / ("planners_cli_" + std::to_string(::getpid()) + ".toml")).string();
  std::ofstream(config) << "[planning]\ndefault_planner = \"warp-drive\"\n";
  out = runCli("plan --config " + config + " --print-config");
  EXPECT_EQ(out.exit_code, 3) << out.text;
  EXPECT_NE(out.text.find("planning.default_planner"), std::string::npos) << out.text;
  EXPECT_NE(out.text.find(std::string(routePlanners()[1].name)), std::string::npos) << out.text;
  std::filesystem::remove(config);
}

TEST(PlannersRegistry, OldSpellingIsAnAliasOfTheDefault) {
  const RoutePlannerInfo* found = nullptr;
  EXPECT_FALSE(findRoutePlanner("rrtstar_lospo", &found).has_value());
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->name, kDefaultRoutePlanner);
  const auto unknown = findRoutePlanner("astar-3d", &found, "planner");
  ASSERT_TRUE(unknown.has_value());
  EXPECT_EQ(unknown->code, PlanErrorCode::kUnknownPlanner);
  EXPECT_EQ(unknown->field, "planner");
}

}  // namespace
}  // namespace skyroute
