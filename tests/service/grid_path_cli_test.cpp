// `skyroute grid path` end to end: runs the built binary (SKYROUTE_CLI) on a small Moving AI map,
// checks the printed times and the --out JSON (length = sum of the segments, every segment in line
// of sight by an independent geometric check, any-angle lengths near the visibility-graph optimum), and that bad
// input names the option and exits with the code of the one table.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "planning/grid/any_angle_search.hpp"
#include "terrain/movingai.hpp"
#include "tests/planning/any_angle_reference.hpp"

namespace skyroute {
namespace {

namespace fs = std::filesystem;

struct CliRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

class GridPathCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("skyroute_grid_path_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    map_ = (dir_ / "wall.map").string();
    std::ofstream f(map_);
    f << "type octile\nheight 12\nwidth 16\nmap\n";
    for (int y = 0; y < 12; ++y) {
      for (int x = 0; x < 16; ++x) f << ((x == 7 && y >= 2) || (x == 11 && y <= 8) ? '@' : '.');
      f << "\n";
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  CliRun run(const std::string& args) {
    const std::string err_file = (dir_ / "stderr.txt").string();
    const std::string cmd = std::string(SKYROUTE_CLI) + " " + args + " 2>" + err_file;
    CliRun r;
    FILE* pipe = popen(cmd.c_str(), "r");
    if (pipe == nullptr) return r;
    char buf[4096];
    std::size_t n;
    while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) r.out.append(buf, n);
    const int status = pclose(pipe);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream e(err_file);
    std::stringstream ss;
    ss << e.rdbuf();
    r.err = ss.str();
    return r;
  }

  fs::path dir_;
  std::string map_;
};

TEST_F(GridPathCli, EveryAlgorithmWritesAValidPathAndPrintsTimes) {
  auto grid = loadMovingAiMap(map_);
  ASSERT_TRUE(grid.ok());
  const GridCell start{2, 10}, goal{14, 1};
  const double optimum = testing::visibilityGraphOptimum(*grid, start, goal);
  for (const std::string algo : {"astar", "theta", "hab-pp", "hab-pp-rrt"}) {
    SCOPED_TRACE(algo);
    const std::string out = (dir_ / (algo + ".json")).string();
    const CliRun r = run("grid path --map " + map_ + " --from 2,10 --to 14,1 --algo " + algo + " --seed 3 --budget-s 10 --out " + out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("length: "), std::string::npos);
    EXPECT_NE(r.out.find("first path time: "), std::string::npos);
    EXPECT_NE(r.out.find("total time: "), std::string::npos);
    std::ifstream f(out);
    const nlohmann::json j = nlohmann::json::parse(f);
    std::vector<GridCell> path;
    for (const auto& p : j.at("points")) path.push_back(GridCell{p.at(0).get<int>(), p.at(1).get<int>()});
    EXPECT_EQ(testing::pathProblem(*grid, path, start, goal), "");
    EXPECT_NEAR(j.at("length").get<double>(), polylineLength(path), 1e-9);
    EXPECT_GE(j.at("length").get<double>(), optimum - 1e-9);
    if (algo == "theta") {
      EXPECT_LE(j.at("length").get<double>(), optimum * 1.015);  // Theta* is near, not at, the optimum
    }
    if (algo != "astar") {  // measured: HAB-PP +10% here with the paper's colony in a 10 s budget
      EXPECT_LE(j.at("length").get<double>(), optimum * 1.15);
    }
  }
}

TEST_F(GridPathCli, SameSeedSamePath) {
  const std::string a = (dir_ / "a.json").string(), b = (dir_ / "b.json").string();
  ASSERT_EQ(run("grid path --map " + map_ + " --from 2,10 --to 14,1 --algo hab-pp-rrt --seed 9 --out " + a).exit_code, 0);
  // The names before --from and --to still work for one release.
  ASSERT_EQ(run("grid path --map " + map_ + " --start 2,10 --goal 14,1 --algo hab-pp-rrt --seed 9 --out " + b).exit_code, 0);
  std::ifstream fa(a), fb(b);
  EXPECT_EQ(nlohmann::json::parse(fa), nlohmann::json::parse(fb));
}

// --window-segments (default 3; 0 turns it off): the same colony (same seed), the output stage's
// local search on top: valid, never longer than without it.
TEST_F(GridPathCli, WindowSegmentsOnlyShortenTheHabPpPath) {
  auto grid = loadMovingAiMap(map_);
  ASSERT_TRUE(grid.ok());
  const std::string plain = (dir_ / "plain.json").string(), windowed = (dir_ / "windowed.json").string();
  const std::string common = "grid path --map " + map_ + " --from 2,10 --to 14,1 --algo hab-pp --seed 5 --budget-s 10";
  ASSERT_EQ(run(common + " --window-segments 0 --out " + plain).exit_code, 0);
  const CliRun r = run(common + " --window-segments 3 --out " + windowed);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream fp(plain), fw(windowed);
  const nlohmann::json a = nlohmann::json::parse(fp), b = nlohmann::json::parse(fw);
  std::vector<GridCell> path;
  for (const auto& p : b.at("points")) path.push_back(GridCell{p.at(0).get<int>(), p.at(1).get<int>()});
  EXPECT_EQ(testing::pathProblem(*grid, path, GridCell{2, 10}, GridCell{14, 1}), "");
  EXPECT_LE(b.at("length").get<double>(), a.at("length").get<double>() + 1e-9);
}

TEST_F(GridPathCli, BadInputNamesTheFieldAndFails) {
  struct Case {
    std::string args;  // after "grid path"
    int exit_code;
    std::string named;  // what the message must name
  };
  const std::string wall = " --map " + map_;
  const std::vector<Case> cases{
      {wall + " --from 7,5 --to 14,1 --algo theta", 2, "--from"},
      {wall + " --from 7,5 --to 14,1 --algo theta", 2, "blocked"},
      {wall + " --from 2,10 --to 40,1 --algo hab-pp", 2, "--to"},
      {wall + " --from '2;10' --to 14,1 --algo astar", 2, "--from"},
      {wall + " --to 14,1 --algo astar", 2, "--from"},
      {wall + " --from 2,10 --to 14,1 --algo astar --out " + (dir_ / "nowhere" / "p.json").string(), 2, "--out"},
      {wall + " --from 2,10 --to 14,1 --algo astar --out " + (dir_ / "p.txt").string(), 2, "--out"},
      {" --map " + (dir_ / "missing.map").string() + " --from 2,10 --to 14,1 --algo astar", 3, "missing.map"},
      {wall + " --from 2,10 --to 14,1 --algo theta --window-segments 3", 2, "--window-segments"},
      {wall + " --from 2,10 --to 14,1 --algo hab-pp --window-segments -1", 2, "--window-segments"},
      {wall + " --from 2,10 --to 14,1 --algo dijkstra", 2, "--algo"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const CliRun r = run("grid path" + c.args);
    EXPECT_EQ(r.exit_code, c.exit_code);
    EXPECT_NE(r.err.find(c.named), std::string::npos) << r.err;
  }
}

TEST_F(GridPathCli, UnreachableGoalExitsWithNoPath) {
  // Close the gap under the first wall: the left part is cut off.
  const std::string closed = (dir_ / "closed.map").string();
  std::ofstream f(closed);
  f << "type octile\nheight 4\nwidth 6\nmap\n..@...\n..@...\n..@...\n..@...\n";
  f.close();
  for (const std::string algo : {"theta", "hab-pp-rrt"}) {
    const CliRun r = run("grid path --map " + closed + " --from 0,0 --to 5,3 --algo " + algo);
    EXPECT_EQ(r.exit_code, 1) << algo;  // planning failed
    EXPECT_NE(r.err.find("no path"), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace skyroute
