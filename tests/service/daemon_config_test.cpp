// skyrouted's configuration: every key printed by describeDaemonConfig parses back to the same
// values; unknown sections and keys, wrong types and values out of range are errors naming the key;
// a malformed file names the line.
#include <gtest/gtest.h>

#include "service/daemon_config.hpp"

namespace skyroute {
namespace {

TEST(DaemonConfig, DescribedConfigurationParsesBackToItself) {
  DaemonConfig config;
  config.dem_path = "/data/dem/N44W072.hgt";
  config.domain = 17;
  config.engine.pipeline.seed = 99;
  config.engine.pipeline.sample_dt_s = 0.5;
  config.engine.pipeline.replan.horizon_s = 30.0;
  config.engine.pipeline.replan.replan_budget_ms = 25.0;
  config.engine.replanning = false;
  config.log_format = "json";
  config.engine.pipeline.replan.rrt_tree_reuse = true;
  config.engine.pipeline.replan.route.tree_reuse.max_nodes = 500;
  const std::string text = describeDaemonConfig(config);
  auto parsed = parseDaemonConfig(text, "described.toml");
  ASSERT_TRUE(parsed.ok()) << parsed.error().describe() << "\n" << text;
  EXPECT_EQ(parsed->dem_path, config.dem_path);
  EXPECT_EQ(parsed->domain, 17);
  EXPECT_EQ(parsed->engine.pipeline.seed, 99u);
  EXPECT_EQ(parsed->engine.pipeline.sample_dt_s, 0.5);
  EXPECT_EQ(parsed->engine.pipeline.replan.horizon_s, 30.0);
  EXPECT_DOUBLE_EQ(parsed->engine.pipeline.replan.replan_budget_ms, 25.0);  // written as budget_s = 0.025
  EXPECT_FALSE(parsed->engine.replanning);
  EXPECT_EQ(parsed->log_format, "json");
  EXPECT_TRUE(parsed->engine.pipeline.replan.rrt_tree_reuse);
  EXPECT_EQ(parsed->engine.pipeline.replan.route.tree_reuse.max_nodes, 500u);
  EXPECT_EQ(describeDaemonConfig(*parsed), text);
}

TEST(DaemonConfig, EmptyFileKeepsTheDefaults) {
  auto parsed = parseDaemonConfig("", "empty.toml");
  ASSERT_TRUE(parsed.ok());
  EXPECT_EQ(describeDaemonConfig(*parsed), describeDaemonConfig(DaemonConfig{}));
}

// Seed 003's equation 3 is selectable beside the trapezoidal profile (the default).
TEST(DaemonConfig, TimeAllocationIsReadAndPrinted) {
  EXPECT_EQ(DaemonConfig{}.engine.pipeline.replan.route.trajectory.time_allocation.method,
            TimeAllocationMethod::kTrapezoidal);
  auto parsed = parseDaemonConfig("[planning]\ntime_allocation = \"constant_speed\"\n", "eq3.toml");
  ASSERT_TRUE(parsed.ok()) << parsed.error().describe();
  EXPECT_EQ(parsed->engine.pipeline.replan.route.trajectory.time_allocation.method,
            TimeAllocationMethod::kConstantSpeed);
  EXPECT_NE(describeDaemonConfig(*parsed).find("time_allocation = \"constant_speed\""), std::string::npos)
      << describeDaemonConfig(*parsed);
}

TEST(DaemonConfig, BadInputNamesTheKeyOrLine) {
  struct Case {
    std::string text, field;
    ErrorCode code;
  };
  const std::vector<Case> cases = {
      {"[planing]\nseed = 1\n", "planing", ErrorCode::kInvalidArgument},
      {"[planning]\nsed = 1\n", "planning.sed", ErrorCode::kInvalidArgument},
      {"[planning]\nseed = \"one\"\n", "planning.seed", ErrorCode::kInvalidArgument},
      {"[planning]\nsample_dt_s = -1\n", "planning.sample_dt_s", ErrorCode::kInvalidArgument},
      {"[planning]\nthreads = 0\n", "planning.threads", ErrorCode::kInvalidArgument},
      {"[planning]\ndefault_planner = \"magic\"\n", "planning.default_planner", ErrorCode::kInvalidArgument},
      {"[planning]\ntime_allocation = \"eq3\"\n", "planning.time_allocation", ErrorCode::kInvalidArgument},
      {"[planning]\nleg_max_iterations = 0\nleg_time_cap_s = 0\n", "planning.leg_max_iterations",
       ErrorCode::kInvalidArgument},
      {"[dds]\ndomain = 300\n", "dds.domain", ErrorCode::kInvalidArgument},
      {"[replanning]\nenabled = 1\n", "replanning.enabled", ErrorCode::kInvalidArgument},
      {"[planning]\nrrt_tree_reuse = \"yes\"\n", "planning.rrt_tree_reuse", ErrorCode::kInvalidArgument},
      {"[planning]\nrrt_tree_reuse_max_nodes = 0\n", "planning.rrt_tree_reuse_max_nodes", ErrorCode::kInvalidArgument},
      {"[log]\nformat = \"xml\"\n", "log.format", ErrorCode::kInvalidArgument},
      {"seed = 1\n", "seed", ErrorCode::kInvalidArgument},
      {"''='x'\n", "\"\"", ErrorCode::kInvalidArgument},
      {"[dds]\n\"\" = 1\n", "dds.\"\"", ErrorCode::kInvalidArgument},
      {"[planning\nseed = 1\n", "bad.toml", ErrorCode::kParseError},
  };
  for (const Case& c : cases) {
    auto parsed = parseDaemonConfig(c.text, "bad.toml");
    ASSERT_FALSE(parsed.ok()) << c.text;
    EXPECT_EQ(parsed.error().code, c.code) << c.text;
    EXPECT_EQ(parsed.error().field, c.field) << c.text << " -> " << parsed.error().describe();
  }
  auto malformed = parseDaemonConfig("[planning\nseed = 1\n", "bad.toml");
  EXPECT_NE(malformed.error().message.find("bad.toml:1:"), std::string::npos) << malformed.error().message;
  // Characters the TOML library mishandles are refused with their line and column: U+FE7F
  // anywhere, and any non-ASCII character outside strings and comments (where TOML allows none);
  // U+FEFF (a byte-order mark) and other non-ASCII text in comments and strings still parse.
  auto odd = parseDaemonConfig("[planning]\nseed = 1\n \xEF\xB9\xBF\n", "odd.toml");
  ASSERT_FALSE(odd.ok());
  EXPECT_EQ(odd.error().code, ErrorCode::kParseError);
  EXPECT_NE(odd.error().message.find("odd.toml:3:2: character U+FE7F"), std::string::npos) << odd.error().message;
  auto bare = parseDaemonConfig("[dds]\ndomin \xC3\xA4 6\n", "bare.toml");
  ASSERT_FALSE(bare.ok());
  EXPECT_NE(bare.error().message.find("bare.toml:2:7: a character outside a string or a comment must be ASCII"),
            std::string::npos)
      << bare.error().message;
  // A quote inside a bare token opens no string: what follows it is still checked.
  auto quote = parseDaemonConfig("[terrain]\ndem = 0le'x \xC8\xA3'\n", "quote.toml");
  ASSERT_FALSE(quote.ok());
  EXPECT_NE(quote.error().message.find("quote.toml:2:13: a character outside"), std::string::npos)
      << quote.error().message;
  // In a multi-line basic string, a non-ASCII character right after a backslash, or first after a
  // line-ending backslash, is refused at its place; elsewhere in such a string it is text.
  for (const char* text : {"[terrain]\ndem = \"\"\"in\\\xC8\xA3\"\"\"\n",
                           "[terrain]\ndem = \"\"\"in\\ \n  \n \xC8\xA3\"\"\"\n",
                           "[terrain]\ndem = \"\"\"in\\  \xC8\xA3\"\"\"\n"}) {
    auto escaped = parseDaemonConfig(text, "ml.toml");
    ASSERT_FALSE(escaped.ok()) << text;
    EXPECT_NE(escaped.error().message.find("ml.toml:"), std::string::npos) << escaped.error().message;
    EXPECT_NE(escaped.error().message.find("non-ASCII character after a backslash"), std::string::npos)
        << escaped.error().message;
  }
  auto multi = parseDaemonConfig("[terrain]\ndem = \"\"\"a\\\\\n\xC8\xA3\\\n  b\xC3\xA4\"\"\"\n", "ml.toml");
  ASSERT_TRUE(multi.ok()) << multi.error().describe();
  EXPECT_EQ(multi->dem_path, "a\\\n\xC8\xA3" "b\xC3\xA4");
  EXPECT_TRUE(parseDaemonConfig("[terrain]\ndem = 'l\xC3\xA4' # \xC3\xA4\n[planning]\nseed = 3\n", "q.toml").ok());
  EXPECT_TRUE(parseDaemonConfig("\xEF\xBB\xBF[terrain]\ndem = \"bom\"\n", "bom.toml").ok());
  auto fine = parseDaemonConfig("# h\xC3\xB6he \xEF\xBB\xBF\n[terrain]\ndem = \"s\xC3\xBC" "d\"\n", "fine.toml");
  ASSERT_TRUE(fine.ok()) << fine.error().describe();
  EXPECT_EQ(fine->dem_path, "s\xC3\xBC" "d");
  auto missing = loadDaemonConfig("/nonexistent/skyrouted.toml");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, ErrorCode::kFileNotFound);
}

TEST(DaemonConfig, Ros2MirrorIsOnByDefaultAndCanBeTurnedOff) {
  EXPECT_TRUE(DaemonConfig{}.ros2_enabled);
  EXPECT_NE(describeDaemonConfig(DaemonConfig{}).find("[ros2]"), std::string::npos);
  auto off = parseDaemonConfig("[ros2]\nenabled = false\n", "ros2.toml");
  ASSERT_TRUE(off.ok()) << off.error().describe();
  EXPECT_FALSE(off->ros2_enabled);
  auto bad = parseDaemonConfig("[ros2]\nenabled = 1\n", "ros2.toml");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().field, "ros2.enabled");
}

TEST(DaemonConfig, HotStandbyRoleAndStrengthsAreReadAndChecked) {
  const DaemonConfig defaults;
  EXPECT_EQ(defaults.role, "primary");
  EXPECT_GT(ownershipStrength(defaults), 0);
  auto standby = parseDaemonConfig(
      "[service]\nrole = \"standby\"\n[dds]\nprimary_strength = 7\nstandby_strength = 3\nliveliness_lease_s = 0.25\n",
      "standby.toml");
  ASSERT_TRUE(standby.ok()) << standby.error().describe();
  EXPECT_EQ(standby->role, "standby");
  EXPECT_EQ(ownershipStrength(*standby), 3);
  EXPECT_DOUBLE_EQ(standby->liveliness_lease_s, 0.25);
  DaemonConfig primary = *standby;
  primary.role = "primary";
  EXPECT_EQ(ownershipStrength(primary), 7);

  const auto refused = [](const std::string& toml) {
    auto parsed = parseDaemonConfig(toml, "bad.toml");
    return parsed.ok() ? std::string("(accepted)") : parsed.error().field;
  };
  EXPECT_EQ(refused("[service]\nrole = \"backup\"\n"), "service.role");
  EXPECT_EQ(refused("[dds]\nprimary_strength = 5\nstandby_strength = 5\n"), "dds.primary_strength");
  EXPECT_EQ(refused("[dds]\nstandby_strength = 200\n"), "dds.primary_strength");  // above the default primary's
  EXPECT_EQ(refused("[dds]\nstandby_strength = -1\n"), "dds.standby_strength");
  EXPECT_EQ(refused("[dds]\nprimary_strength = 3000000000\n"), "dds.primary_strength");
  EXPECT_EQ(refused("[dds]\nprimary_strength = 1.5\n"), "dds.primary_strength");
  EXPECT_EQ(refused("[dds]\nliveliness_lease_s = 0\n"), "dds.liveliness_lease_s");

  // The daemon checks again after --role (validateDaemonConfig).
  DaemonConfig overridden;
  overridden.role = "secondary";
  ASSERT_FALSE(validateDaemonConfig(overridden).ok());
  EXPECT_EQ(validateDaemonConfig(overridden).error().field, "service.role");
  overridden.role = "standby";
  EXPECT_TRUE(validateDaemonConfig(overridden).ok());
}

TEST(DaemonConfig, ShardGroupIsReadPrintedAndRefusedWithAStandby) {
  EXPECT_EQ(DaemonConfig{}.shard_group, "") << "not sharded unless asked";
  // The service id names the daemon on the wire and in every log line: an id (text_bounds.hpp).
  auto spaced = parseDaemonConfig("[dds]\nservice_id = \"my daemon\"\n", "id.toml");
  ASSERT_FALSE(spaced.ok());
  EXPECT_EQ(spaced.error().field, "dds.service_id");
  EXPECT_NE(spaced.error().message.find("may hold only A-Z a-z 0-9 _ - ."), std::string::npos) << spaced.error().message;
  auto sharded = parseDaemonConfig("[service]\nshard_group = \"east\"\n[dds]\nservice_id = \"shard-1\"\n", "shard.toml");
  ASSERT_TRUE(sharded.ok()) << sharded.error().describe();
  EXPECT_EQ(sharded->shard_group, "east");
  EXPECT_EQ(sharded->service_id, "shard-1");
  // --print-config shows the key, and what it prints reads back the same.
  const std::string text = describeDaemonConfig(*sharded);
  EXPECT_NE(text.find("shard_group = \"east\""), std::string::npos) << text;
  auto again = parseDaemonConfig(text, "printed.toml");
  ASSERT_TRUE(again.ok()) << again.error().describe();
  EXPECT_EQ(again->shard_group, "east");

  const auto refused = [](const std::string& toml) {
    auto parsed = parseDaemonConfig(toml, "bad.toml");
    return parsed.ok() ? std::string("(accepted)") : parsed.error().field;
  };
  EXPECT_EQ(refused("[service]\nshard_group = \"east\"\nrole = \"standby\"\n"), "service.shard_group");
  EXPECT_EQ(refused("[service]\nshard_group = \"a;b\"\n"), "service.shard_group");
  EXPECT_EQ(refused("[service]\nshard_group = 3\n"), "service.shard_group");
  // The daemon checks again after --shard-group and --role.
  DaemonConfig overridden;
  overridden.shard_group = "east";
  EXPECT_TRUE(validateDaemonConfig(overridden).ok());
  overridden.role = "standby";
  ASSERT_FALSE(validateDaemonConfig(overridden).ok());
  EXPECT_EQ(validateDaemonConfig(overridden).error().field, "service.shard_group");
}

}  // namespace
}  // namespace skyroute
