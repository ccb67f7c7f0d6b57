// The text bounds (service/text_bounds.hpp) as a user of `skyroute plan` meets them: an id from
// the command line or a mission file that could not name a topic, a log line or a CSV row is
// refused before anything is planned, naming the field.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/cli_run.hpp"
#include "tests/test_data.hpp"
#include "tests/test_folder.hpp"
#include "tests/text_file.hpp"

namespace skyroute {
namespace {

using testing::runCli;

class TextBoundsCli : public testing::TestFolderTest {
 protected:
  TextBoundsCli() : TestFolderTest("text_bounds_cli_") {}
};

TEST_F(TextBoundsCli, AVehicleIdWithASpaceOrACommaIsRefusedNamingIt) {
  const auto spaced = runCli("plan --vehicle 'uav 1' --from 46.93,15.10,1200 --to 46.96,15.12,1200");
  EXPECT_EQ(spaced.exit_code, 2) << spaced.text;
  EXPECT_NE(spaced.text.find("vehicle_id may hold only A-Z a-z 0-9 _ - ."), std::string::npos) << spaced.text;
  const auto formula = runCli("plan --vehicle '=1+1,x' --from 46.93,15.10,1200 --to 46.96,15.12,1200");
  EXPECT_EQ(formula.exit_code, 2) << formula.text;
  EXPECT_NE(formula.text.find("vehicle_id"), std::string::npos) << formula.text;
}

TEST_F(TextBoundsCli, AMissionFileWithA70000CharacterVehicleIdIsRefusedAndNothingIsWritten) {
  nlohmann::json mission = nlohmann::json::parse(testing::readTextFile(testing::projectDataPath("missions/demo_mission.json")));
  mission["vehicle_id"] = std::string(70000, 'v');
  const std::string path = (dir_ / "long_id.json").string();
  std::ofstream(path) << mission.dump();
  const std::string csv = (dir_ / "out.csv").string();
  const auto out = runCli("plan --mission " + path + " --out " + csv);
  EXPECT_EQ(out.exit_code, 3) << out.text.substr(0, 2000);  // an input file invalid
  EXPECT_NE(out.text.find("vehicle_id has 70000 characters, more than the limit of 64"), std::string::npos)
      << out.text.substr(0, 2000);
  EXPECT_LT(out.text.size(), 2000u) << "the refusal repeats the whole id";
  EXPECT_FALSE(std::filesystem::exists(csv));
}

}  // namespace
}  // namespace skyroute
