// The `skyroute grid solve` and `skyroute mission --map` commands, run as a user would: JSON lines
// checked against the scenario's optimal lengths and against Dijkstra, and bad input giving a
// message that names the option and the exit code of the one table.
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "planning/grid/grid_search.hpp"
#include "terrain/movingai.hpp"
#include "tests/cli_run.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

using Output = testing::CliOutput;

Output run(const std::string& args) { return testing::runCli(args); }

std::vector<nlohmann::json> jsonLines(const std::string& text) {
  std::vector<nlohmann::json> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line.front() == '{') lines.push_back(nlohmann::json::parse(line));
  return lines;
}

TEST(GridCli, SolveMatchesScenarioForEveryAlgorithm) {
  SKYROUTE_REQUIRE_SHARED(map, "movingai/room-32-32-4.map");
  SKYROUTE_REQUIRE_SHARED(scen, "movingai/room-32-32-4-random-1.scen");
  auto problems = loadMovingAiScenario(scen);
  ASSERT_TRUE(problems.ok());
  for (const std::string algo : {"astar", "dijkstra", "dstar-lite", "mmdstar"}) {
    const Output out = run("grid solve --map " + map + " --scen " + scen + " --algo " + algo + " --limit 60");
    ASSERT_EQ(out.exit_code, 0) << algo << "\n" << out.text;
    const auto lines = jsonLines(out.text);
    ASSERT_EQ(lines.size(), 61u) << algo;
    for (std::size_t i = 0; i < 60; ++i) {
      const auto& j = lines[i];
      const MovingAiProblem& pr = (*problems)[i];
      EXPECT_EQ(j["start"], nlohmann::json({pr.start.x, pr.start.y})) << algo << " " << i;
      EXPECT_EQ(j["goal"], nlohmann::json({pr.goal.x, pr.goal.y}));
      EXPECT_NEAR(j["cost"].get<double>(), pr.optimal_length, 1e-3) << algo << " " << i;
      EXPECT_NEAR(j["optimal"].get<double>(), pr.optimal_length, 1e-9);
      EXPECT_GE(j["time_ms"].get<double>(), 0.0);
      EXPECT_TRUE(j.contains("expansions"));
    }
    EXPECT_EQ(lines.back()["problems"], 60);
    EXPECT_EQ(lines.back()["mismatches"], 0);
  }
}

std::string writeFile(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  FILE* f = std::fopen(path.c_str(), "w");
  std::fputs(text.c_str(), f);
  std::fclose(f);
  return path;
}

// A scenario that prints its optimal lengths with two decimals: the right costs agree to those
// digits (sqrt(2) = 1.41421 against "1.41", an error of 0.0042, beyond the old absolute 1e-3) and
// pass; a length wrong by more than half a unit of the second decimal is still caught.
TEST(GridCli, SolveComparesAtThePrecisionTheScenarioPrinted) {
  const std::string map = writeFile("open4.map", "type octile\nheight 4\nwidth 4\nmap\n....\n....\n....\n....\n");
  const std::string right = writeFile("two_decimals.scen",
                                      "version 1\n0\topen4.map\t4\t4\t0\t0\t1\t1\t1.41\n"
                                      "0\topen4.map\t4\t4\t0\t0\t3\t1\t3.41\n"
                                      "0\topen4.map\t4\t4\t0\t0\t3\t0\t3\n");
  const Output ok = run("grid solve --map " + map + " --scen " + right);
  ASSERT_EQ(ok.exit_code, 0) << ok.text;
  const auto lines = jsonLines(ok.text);
  ASSERT_EQ(lines.size(), 4u) << ok.text;
  EXPECT_EQ(lines.back()["mismatches"], 0);
  EXPECT_NEAR(lines.back()["max_abs_error"].get<double>(), std::sqrt(2.0) - 1.41, 1e-9);
  EXPECT_NEAR(lines[0]["tolerance"].get<double>(), 0.005, 1e-12);
  EXPECT_NEAR(lines[2]["tolerance"].get<double>(), 0.5, 1e-12);  // "3": its own digits, not the file's
  EXPECT_NE(ok.text.find("largest error against the scenario's optimal lengths: 0.0042"), std::string::npos) << ok.text;

  const std::string wrong = writeFile("wrong_second_decimal.scen", "version 1\n0\topen4.map\t4\t4\t0\t0\t1\t1\t1.40\n");
  const Output bad = run("grid solve --map " + map + " --scen " + wrong);
  EXPECT_EQ(bad.exit_code, 1) << bad.text;
  EXPECT_EQ(jsonLines(bad.text).back()["mismatches"], 1);
  EXPECT_NE(bad.text.find("1 costs differ beyond the printed digits, the first at problem 0"), std::string::npos)
      << bad.text;
}

// A scenario printed with six significant digits (%g, as the Moving AI maze files are): a length
// of 761 + 169 sqrt(2) = 1000.00209 is printed "1000", and 2 + 3 sqrt(2) = 6.242641 "6.24264" in
// the same file. Each line holds to its own digits: "1000" to half a unit (the cost rounds to
// it), "6.24264" to 5e-6. Before, "1000" was held to the file's most decimals (1e-5) and the
// right cost was called wrong, as 14 of maze512-8-3's 1,303 were (1239.0042 against "1239").
TEST(GridCli, SolveHoldsEachLengthToItsOwnPrintedDigits) {
  constexpr int kWidth = 931, kHeight = 170;
  std::string map = "type octile\nheight " + std::to_string(kHeight) + "\nwidth " + std::to_string(kWidth) + "\nmap\n";
  for (int row = 0; row < kHeight; ++row) map += std::string(kWidth, '.') + "\n";
  const std::string map_path = writeFile("open931x170.map", map);
  const std::string scen = writeFile("six_significant_digits.scen",
                                     "version 1\n"
                                     "0\topen931x170.map\t931\t170\t0\t0\t930\t169\t1000\n"
                                     "0\topen931x170.map\t931\t170\t0\t0\t5\t3\t6.24264\n");
  const Output out = run("grid solve --map " + map_path + " --scen " + scen);
  EXPECT_EQ(out.exit_code, 0) << out.text;
  const auto lines = jsonLines(out.text);
  ASSERT_EQ(lines.size(), 3u) << out.text;
  EXPECT_NEAR(lines[0]["cost"].get<double>(), 761 + 169 * std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(lines[0]["tolerance"].get<double>(), 0.5, 1e-12);
  EXPECT_NEAR(lines[1]["tolerance"].get<double>(), 5e-6, 1e-15);
  EXPECT_EQ(lines.back()["mismatches"], 0);
  EXPECT_NE(out.text.find("every cost agrees to the printed digits"), std::string::npos) << out.text;

  // A cost off by more than half a unit of its last digit is still wrong: 6.24265 is 9.3e-6 away.
  const std::string wrong = writeFile("six_significant_digits_wrong.scen",
                                      "version 1\n0\topen931x170.map\t931\t170\t0\t0\t5\t3\t6.24265\n");
  const Output bad = run("grid solve --map " + map_path + " --scen " + wrong);
  EXPECT_EQ(bad.exit_code, 1) << bad.text;
  EXPECT_EQ(jsonLines(bad.text).back()["mismatches"], 1);
}

// The shared Moving AI scenarios (8room prints six significant digits, room-32 eight decimals):
// every cost of the first 1000 problems agrees with the printed optimal lengths; exit 0.
TEST(GridCli, SolveAgreesWithSharedScenariosToTheirPrintedDigits) {
  SKYROUTE_REQUIRE_SHARED(room_map, "movingai/room-32-32-4.map");
  SKYROUTE_REQUIRE_SHARED(room_scen, "movingai/room-32-32-4-random-1.scen");
  SKYROUTE_REQUIRE_SHARED(rooms_map, "movingai/8room_000.map");
  SKYROUTE_REQUIRE_SHARED(rooms_scen, "movingai/8room_000.map.scen");
  for (const auto& [map, scen] : {std::pair{room_map, room_scen}, std::pair{rooms_map, rooms_scen}}) {
    const Output out = run("grid solve --map " + map + " --scen " + scen + " --limit 1000");
    EXPECT_EQ(out.exit_code, 0) << scen << "\n" << out.text.substr(out.text.rfind('{'));
    EXPECT_EQ(jsonLines(out.text).back()["mismatches"], 0) << scen;
    EXPECT_NE(out.text.find("every cost agrees to the printed digits"), std::string::npos) << scen;
  }
}

TEST(GridCli, SolveRejectsMissingFiles) {
  const Output out = run("grid solve --map /nonexistent.map --scen /nonexistent.scen");
  EXPECT_EQ(out.exit_code, 3);  // an input file unreadable
  EXPECT_NE(out.text.find("--map"), std::string::npos) << out.text;
  EXPECT_NE(out.text.find("/nonexistent.map"), std::string::npos) << out.text;
  EXPECT_EQ(run("grid solve --map /nonexistent.map --scen /nonexistent.scen --algo magic").exit_code, 2);
}

// Exit 1 is for a wrong cost only: a scenario whose optimal length is wrong, here by 1.
TEST(GridCli, SolveExitsOneOnlyWhenACostIsWrong) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("skyroute_grid_cli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string map = (dir / "open.map").string();
  std::ofstream(map) << "type octile\nheight 4\nwidth 4\nmap\n....\n....\n....\n....\n";
  const std::string right = (dir / "right.scen").string();
  const std::string wrong = (dir / "wrong.scen").string();
  std::ofstream(right) << "version 1\n0\topen.map\t4\t4\t0\t0\t3\t0\t3\n";
  std::ofstream(wrong) << "version 1\n0\topen.map\t4\t4\t0\t0\t3\t0\t4\n";
  const Output ok = run("grid solve --map " + map + " --scen " + right);
  EXPECT_EQ(ok.exit_code, 0) << ok.text;
  const Output off = run("grid solve --map " + map + " --scen " + wrong);
  EXPECT_EQ(off.exit_code, 1) << off.text;
  EXPECT_NE(off.text.find("1 of 1 costs are wrong"), std::string::npos) << off.text;
  std::filesystem::remove_all(dir);
}

TEST(GridCli, MissionPrintsOrderMatrixAndLegs) {
  SKYROUTE_REQUIRE_SHARED(map, "movingai/random-64-64-20.map");
  auto grid = loadMovingAiMap(map);
  ASSERT_TRUE(grid.ok());
  // Begin and four points in begin's component, found deterministically.
  const GridCell begin{0, 0};
  GridCell b = begin;
  for (int i = 0; grid->blocked(b); ++i) b = {i % 64, i / 64};
  const auto reach = reachableCells(*grid, b);
  std::vector<GridCell> pts;
  for (int i = 64 * 64 - 1; i >= 0 && pts.size() < 5; i -= 397) {
    const GridCell c{i % 64, i / 64};
    if (reach[grid->index(c)] && !(c == b)) pts.push_back(c);
  }
  ASSERT_EQ(pts.size(), 5u);
  auto cell = [](GridCell c) { return std::to_string(c.x) + "," + std::to_string(c.y); };
  std::string args = "mission --map " + map + " --from " + cell(b) + " --to " + cell(pts[4]) + " --via '";
  for (int i = 0; i < 4; ++i) args += (i ? ";" : "") + cell(pts[i]);
  args += "'";
  for (const std::string algo : {"mmdstar", "dstar-lite"}) {
    const Output out = run(args + " --algo " + algo + " --json");
    ASSERT_EQ(out.exit_code, 0) << out.text;
    const auto lines = jsonLines(out.text);
    ASSERT_EQ(lines.size(), 1u);
    const auto& j = lines[0];
    ASSERT_EQ(j["order"].size(), 6u);
    EXPECT_EQ(j["order"].front(), "B");
    EXPECT_EQ(j["order"].back(), "E");
    EXPECT_EQ(j["cost_maps"], algo == "mmdstar" ? 5 : 20);
    // Every leg's cost is Dijkstra's, and they add up to the cost.
    double sum = 0.0;
    const std::vector<GridCell> all{b, pts[0], pts[1], pts[2], pts[3], pts[4]};
    auto index = [](const std::string& label) { return label == "B" ? 0 : label == "E" ? 5 : std::stoi(label.substr(1)); };
    for (const auto& leg : j["legs"]) {
      const int from = index(leg["from"].get<std::string>());
      const int to = index(leg["to"].get<std::string>());
      const GridPath ref = dijkstraSearch(*grid, all[from], all[to]);
      EXPECT_NEAR(leg["cost"].get<double>(), ref.cost, 1e-9);
      sum += leg["cost"].get<double>();
    }
    EXPECT_NEAR(sum, j["cost"].get<double>(), 1e-9);
    EXPECT_GT(j["expansions"].get<long>(), 0);
  }
  const Output text = run(args);
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.text.find("order"), std::string::npos);
  EXPECT_NE(text.text.find("cost matrix"), std::string::npos);

  // The names before --from/--via/--to still work for one release, and give the same plan.
  std::string old_args = "mission --map " + map + " --begin " + cell(b) + " --end " + cell(pts[4]) + " --points";
  for (int i = 0; i < 4; ++i) old_args += " " + cell(pts[i]);
  const Output old_names = run(old_args + " --json");
  ASSERT_EQ(old_names.exit_code, 0) << old_names.text;
  EXPECT_EQ(jsonLines(old_names.text)[0]["order"], jsonLines(run(args + " --json").text)[0]["order"]);
}

TEST(GridCli, MissionNamesABadPoint) {
  SKYROUTE_REQUIRE_SHARED(map, "movingai/random-64-64-20.map");
  auto grid = loadMovingAiMap(map);
  ASSERT_TRUE(grid.ok());
  GridCell wall{0, 0}, free_a{0, 0}, free_b{0, 0};
  for (int i = 0; i < 64 * 64; ++i) {
    const GridCell c{i % 64, i / 64};
    if (grid->blocked(c)) wall = c;
  }
  const auto reach_from = [&](GridCell s) { return reachableCells(*grid, s); };
  for (int i = 0; i < 64 * 64; ++i) {
    const GridCell c{i % 64, i / 64};
    if (grid->passable(c)) {
      free_a = c;
      break;
    }
  }
  const auto reach = reach_from(free_a);
  for (int i = 64 * 64 - 1; i >= 0; --i) {
    const GridCell c{i % 64, i / 64};
    if (reach[grid->index(c)]) {
      free_b = c;
      break;
    }
  }
  auto cell = [](GridCell c) { return std::to_string(c.x) + "," + std::to_string(c.y); };
  const std::string base = "mission --map " + map + " --from " + cell(free_a) + " --to " + cell(free_b);
  Output out = run(base + " --via " + cell(wall));
  EXPECT_EQ(out.exit_code, 2);
  EXPECT_NE(out.text.find("--via[0]"), std::string::npos) << out.text;
  EXPECT_NE(out.text.find("obstacle"), std::string::npos) << out.text;
  out = run(base + " --via 900,3");
  EXPECT_EQ(out.exit_code, 2);
  EXPECT_NE(out.text.find("--via[0]"), std::string::npos) << out.text;
  EXPECT_NE(out.text.find("outside"), std::string::npos) << out.text;
  out = run(base + " --via " + cell(free_b));
  EXPECT_EQ(out.exit_code, 2);
  EXPECT_NE(out.text.find("duplicates"), std::string::npos) << out.text;
  out = run(base + " --via banana");
  EXPECT_EQ(out.exit_code, 2);
  EXPECT_NE(out.text.find("--via[0]"), std::string::npos) << out.text;
  out = run("mission --map /nonexistent.map --from 1,1 --to 2,2");
  EXPECT_EQ(out.exit_code, 3);
  EXPECT_NE(out.text.find("/nonexistent.map"), std::string::npos) << out.text;
  out = run(base + " --fixed-order");  // lat/lon missions only
  EXPECT_EQ(out.exit_code, 2);
  EXPECT_NE(out.text.find("--fixed-order"), std::string::npos) << out.text;
}

}  // namespace
}  // namespace skyroute
