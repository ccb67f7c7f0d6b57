// `skyroute fleet` end to end: the JSON of --out in the documented shape and checked here on its
// own (one entry per step, legal moves, no two vehicles in one cell or swapping, every task on
// its vehicle's path), the PNG readable with one colour per vehicle, and bad input refused with a
// message naming the option and item.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <memory>
#include <tuple>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace {

namespace fs = std::filesystem;

struct CliRun {
  int code = -1;
  std::string out;
  std::string err;
};

class FleetCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("skyroute_fleet_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    // The paper's 5 x 5 example with its conflict at (C,1) (seed 002, Fig. 3).
    std::ofstream map(dir_ / "five.map");
    map << "type octile\nheight 5\nwidth 5\nmap\n"
        << "@@.@@\n.....\n@@.@.\n@@.@.\n@@.@@\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  CliRun run(const std::string& args) const {
    const fs::path out = dir_ / "stdout.txt";
    const fs::path err = dir_ / "stderr.txt";
    const std::string cmd = std::string(SKYROUTE_CLI) + " fleet " + args + " >" + out.string() + " 2>" + err.string();
    const int status = std::system(cmd.c_str());
    CliRun r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    auto slurp = [](const fs::path& p) {
      std::ifstream f(p);
      std::stringstream s;
      s << f.rdbuf();
      return s.str();
    };
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
  }
  std::string map() const { return (dir_ / "five.map").string(); }

  fs::path dir_;
};

TEST_F(FleetCli, WritesAConflictFreePlanAsJsonAndPng) {
  const std::string json_path = (dir_ / "plan.json").string();
  const std::string png_path = (dir_ / "plan.png").string();
  const CliRun r = run("--map " + map() + " --vehicles '1,1;2,0' --tasks '4,1;4,3;2,3;2,4' --out " + json_path +
                    " --png " + png_path);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("makespan 10"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("conflict-free: yes"), std::string::npos) << r.out;

  std::ifstream f(json_path);
  const nlohmann::json doc = nlohmann::json::parse(f);
  const int makespan = doc.at("makespan").get<int>();
  EXPECT_EQ(makespan, 10);
  const auto& vehicles = doc.at("vehicles");
  ASSERT_EQ(vehicles.size(), 2u);
  std::set<std::pair<int, int>> tasks_done;
  std::vector<std::vector<std::pair<int, int>>> paths;
  for (const auto& v : vehicles) {
    const auto& path = v.at("path");
    ASSERT_EQ(static_cast<int>(path.size()), makespan + 1);
    std::vector<std::pair<int, int>> cells;
    for (int t = 0; t <= makespan; ++t) {
      ASSERT_EQ(path[t].size(), 3u);
      EXPECT_EQ(path[t][0].get<int>(), t);
      cells.emplace_back(path[t][1].get<int>(), path[t][2].get<int>());
      if (t > 0) {
        EXPECT_LE(std::abs(cells[t].first - cells[t - 1].first) + std::abs(cells[t].second - cells[t - 1].second), 1);
      }
    }
    const std::pair<int, int> depot{v.at("depot")[0].get<int>(), v.at("depot")[1].get<int>()};
    EXPECT_EQ(cells.front(), depot);
    EXPECT_EQ(cells.back(), depot);
    for (const auto& task : v.at("tasks")) {
      const std::pair<int, int> c{task[0].get<int>(), task[1].get<int>()};
      EXPECT_NE(std::find(cells.begin(), cells.end(), c), cells.end());
      EXPECT_TRUE(tasks_done.insert(c).second);
    }
    paths.push_back(cells);
  }
  EXPECT_EQ(tasks_done.size(), 4u);
  for (int t = 0; t <= makespan; ++t) {
    EXPECT_NE(paths[0][t], paths[1][t]) << "step " << t;
    if (t > 0) {
      EXPECT_FALSE(paths[0][t] == paths[1][t - 1] && paths[1][t] == paths[0][t - 1]) << "swap at " << t;
    }
  }
  // Vehicle 1 (depot (2, 0)) waits at (C,0) while vehicle 0 passes (C,1).
  EXPECT_EQ(paths[1][1], (std::pair<int, int>{2, 0}));

  GDALAllRegister();
  std::unique_ptr<GDALDataset> png(static_cast<GDALDataset*>(GDALOpen(png_path.c_str(), GA_ReadOnly)));
  ASSERT_TRUE(png);
  ASSERT_EQ(png->GetRasterCount(), 3);
  const int w = png->GetRasterXSize();
  const int h = png->GetRasterYSize();
  EXPECT_EQ(w, h);  // square cells on a square grid
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  ASSERT_EQ(png->RasterIO(GF_Read, 0, 0, w, h, rgb.data(), w, h, GDT_Byte, 3, nullptr, 3, 3 * w, 1, nullptr), CE_None);
  std::set<std::tuple<int, int, int>> colours;
  for (std::size_t i = 0; i < rgb.size(); i += 3) colours.insert({rgb[i], rgb[i + 1], rgb[i + 2]});
  // White free cells, grey walls and at least one colour per vehicle.
  EXPECT_GE(colours.size(), 4u);
  EXPECT_TRUE(colours.count({255, 255, 255}));
}

TEST_F(FleetCli, AllAllocatorsAgreeOnTheObviousInstance) {
  for (const char* algo : {"greedy", "ga", "exact"}) {
    const CliRun r = run("--map " + map() + " --vehicles '1,1;2,0' --tasks '4,1;4,3;2,3;2,4' --algo " + algo + " --seed 3");
    ASSERT_EQ(r.code, 0) << algo << ": " << r.err;
    EXPECT_NE(r.out.find("makespan 10"), std::string::npos) << algo << ": " << r.out;
  }
}

TEST_F(FleetCli, BadInputIsRefusedWithTheItemNamed) {
  CliRun r = run("--map " + map() + " --vehicles '1,1;2,0' --tasks '4,1;0,0'");  // (0,0) is a wall
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("--tasks"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("task 1"), std::string::npos) << r.err;

  r = run("--map " + map() + " --vehicles '1,1;2' --tasks '4,1'");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--vehicles"), std::string::npos) << r.err;

  r = run("--map " + map() + " --vehicles '1,1;1,1' --tasks '4,1'");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("vehicle 1"), std::string::npos) << r.err;

  r = run("--map " + map() + " --vehicles '1,1' --tasks '4,1;4,3;2,3' --capacity 2");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("capacity"), std::string::npos) << r.err;

  r = run("--map " + map() + " --vehicles '1,1' --tasks '4,1' --algo magic");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--algo"), std::string::npos) << r.err;

  r = run("--map " + (dir_ / "missing.map").string() + " --vehicles '1,1' --tasks '4,1'");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("missing.map"), std::string::npos) << r.err;

  r = run("--vehicles '1,1' --tasks '4,1'");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--map"), std::string::npos) << r.err;

  r = run("--map " + map() + " --vehicles '1,1' --tasks '4,1' --out /nonexistent-dir/plan.json");
  EXPECT_EQ(r.code, 4);
  EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
}

}  // namespace
