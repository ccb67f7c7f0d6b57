// Every subcommand's --help (terrain's and gcs's aside): a short example in its footer, every default shown, and the
// exit-code table last.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "service/cli/exit_codes.hpp"
#include "tests/cli_run.hpp"

namespace skyroute {
namespace {

struct HelpCase {
  std::string command;
  std::vector<std::pair<std::string, std::string>> defaults;  // option, its default
};

// The --help line of an option ("  --algo TEXT:{astar,...}=astar  ..."), "" when absent.
std::string optionLine(const std::string& help, const std::string& option) {
  const auto at = help.find("\n  " + option + " ");
  if (at == std::string::npos) return "";
  return help.substr(at + 1, help.find('\n', at + 1) - at - 1);
}

TEST(CliHelp, EveryCommandHasAnExampleItsDefaultsAndTheExitCodeTable) {
  const std::vector<HelpCase> cases{
      {"grid solve", {{"--algo", "astar"}}},
      {"grid path", {{"--seed", "1"}, {"--budget-s", "60"}, {"--window-segments", "3"}}},
      {"grid", {}},
      {"mission",
       {{"--algo", "mmdstar"}, {"--clearance-m", "30"}, {"--ceiling-m", "5000"}, {"--cell-size-m", "90"},
        {"--out-geometry", "legs"}, {"--max-speed-mps", "30"}, {"--min-turn-radius-m", "0"}}},
      {"fleet",
       {{"--algo", "greedy"}, {"--seed", "1"}, {"--capacity", "0"}, {"--budget-s", "60"}, {"--wait", "120"},
        {"--clearance-m", "30"}, {"--ceiling-m", "5000"}, {"--vref-mps", "20"}, {"--max-speed-mps", "30"},
        {"--max-accel-mps2", "4"}, {"--max-climb-mps", "5"}, {"--max-descent-mps", "4"}, {"--min-turn-radius-m", "0"},
        {"--cell-size-m", "90"}}},
      {"plan",
       {{"--seed", "1"}, {"--iterations", "3000"}, {"--budget-s", "10"}, {"--dt", "0.2"}, {"--clearance-m", "30"},
        {"--vref-mps", "20"}, {"--max-speed-mps", "30"}, {"--min-turn-radius-m", "0"}}},
      {"planners", {}},
      {"request",
       {{"--domain", "0"}, {"--wait", "30"}, {"--clearance-m", "30"}, {"--ceiling-m", "5000"}, {"--vref-mps", "20"},
        {"--max-speed-mps", "30"}, {"--max-accel-mps2", "4"}, {"--max-climb-mps", "5"}, {"--max-descent-mps", "4"},
        {"--min-turn-radius-m", "0"}}},
      {"cancel", {{"--domain", "0"}, {"--wait", "10"}}},
      {"status", {{"--domain", "0"}, {"--wait", "3"}}},
      {"record", {{"--domain", "0"}, {"--count", "0"}, {"--timeout", "0"}}},
      {"replay", {{"--domain", "0"}, {"--speed", "1"}, {"--readers", "0"}, {"--wait", "10"}}},
      {"px4", {{"--domain", "0"}, {"--rate-hz", "50"}, {"--silence-timeout", "3"}, {"--duration", "0"}}},
  };
  for (const HelpCase& c : cases) {
    SCOPED_TRACE(c.command);
    const auto r = testing::runCli(c.command + " --help");
    ASSERT_EQ(r.exit_code, 0) << r.text;
    const auto example = r.text.find("Example");
    ASSERT_NE(example, std::string::npos) << r.text;
    EXPECT_NE(r.text.find("skyroute " + c.command, example), std::string::npos) << "the example runs another command";
    // The table ends the help.
    const std::string table(cli::kExitCodeTable);
    const auto at = r.text.rfind(table);
    ASSERT_NE(at, std::string::npos) << r.text;
    EXPECT_EQ(r.text.find_first_not_of(" \n", at + table.size()), std::string::npos) << r.text;
    for (const auto& [option, value] : c.defaults) {
      const std::string line = optionLine(r.text, option);
      ASSERT_FALSE(line.empty()) << option << " is not in\n" << r.text;
      const auto shown = line.find("=" + value);
      ASSERT_NE(shown, std::string::npos) << line;
      // The default ends there ("=3000", not "=30" of "=3000").
      const std::size_t after = shown + 1 + value.size();
      EXPECT_TRUE(after == line.size() || line[after] == ' ') << line;
    }
  }
}

// The old option names are hidden from --help but still accepted (tested with each command).
TEST(CliHelp, OldOptionNamesAreHidden) {
  EXPECT_EQ(testing::runCli("mission --help").text.find("--begin"), std::string::npos);
  EXPECT_EQ(testing::runCli("mission --help").text.find("--points"), std::string::npos);
  EXPECT_EQ(testing::runCli("grid path --help").text.find("--start"), std::string::npos);
  EXPECT_EQ(testing::runCli("fleet --help").text.find("--cell-size "), std::string::npos);
  EXPECT_EQ(testing::runCli("request --help").text.find("--begin"), std::string::npos);
  EXPECT_EQ(testing::runCli("request --help").text.find("--points"), std::string::npos);
}

}  // namespace
}  // namespace skyroute
