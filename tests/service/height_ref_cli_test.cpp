// `skyroute plan --height-ref`: points given as heights above the WGS 84 ellipsoid plan exactly as
// the same points given AMSL (ellipsoidal height minus the EGM96 undulation there), from the
// options and from a mission file's "height_ref"; bad values and contradictions are usage errors
// naming the option.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "service/height_datum.hpp"
#include "tests/cli_run.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

using testing::runCli;

struct Point {
  double lat_deg, lon_deg, alt_amsl_m;
};
// A short reproducible leg across the embedded terrain (ground below 922 m AMSL).
constexpr Point kFrom{46.90, 15.03, 1100.0};
constexpr Point kTo{46.97, 15.12, 1150.0};

class HeightRefCli : public ::testing::Test {
 protected:
  void SetUp() override {
    auto geoid = Egm96Geoid::load();
    ASSERT_TRUE(geoid.ok()) << geoid.error().describe();  // proj-data is a build dependency
    from_n_m_ = *geoid->undulationM(kFrom.lat_deg, kFrom.lon_deg);
    to_n_m_ = *geoid->undulationM(kTo.lat_deg, kTo.lon_deg);
    const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    dir_ = std::filesystem::path(::testing::TempDir()) / ("skyroute_height_ref_cli_test_" + test);
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  static std::string triple(const Point& p, double alt_m) {
    std::ostringstream s;
    s.precision(17);
    s << p.lat_deg << "," << p.lon_deg << "," << alt_m;
    return s.str();
  }
  std::string common(const std::string& out) const {
    return " --dem " + testing::projectDataPath("default_terrain.tif") + " --iterations 800 --budget-s 0 --out " +
           (dir_ / out).string();
  }
  nlohmann::json samples(const std::string& out) const {
    std::ifstream in(dir_ / out);
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    return j.is_discarded() ? nlohmann::json() : j["samples"];
  }

  double from_n_m_ = 0.0, to_n_m_ = 0.0;
  std::filesystem::path dir_;
};

TEST_F(HeightRefCli, EllipsoidalPointsPlanAsTheirAmslEquivalents) {
  // The undulation here is tens of metres, so treating one height as the other would show.
  ASSERT_GT(std::abs(from_n_m_), 10.0);
  const std::string ellipsoidal = " --from " + triple(kFrom, kFrom.alt_amsl_m + from_n_m_) + " --to " +
                                  triple(kTo, kTo.alt_amsl_m + to_n_m_);
  const auto amsl = runCli("plan --from " + triple(kFrom, kFrom.alt_amsl_m) + " --to " + triple(kTo, kTo.alt_amsl_m) +
                           common("amsl.json"));
  ASSERT_EQ(amsl.exit_code, 0) << amsl.text;
  const auto converted = runCli("plan --height-ref ellipsoid" + ellipsoidal + common("ellipsoid.json"));
  ASSERT_EQ(converted.exit_code, 0) << converted.text;
  const auto unconverted = runCli("plan --height-ref amsl" + ellipsoidal + common("unconverted.json"));
  ASSERT_EQ(unconverted.exit_code, 0) << unconverted.text;

  const nlohmann::json a = samples("amsl.json"), e = samples("ellipsoid.json"), u = samples("unconverted.json");
  ASSERT_GT(a.size(), 10u);
  ASSERT_EQ(e.size(), a.size());  // the same mission, so the same trajectory
  for (std::size_t i : {std::size_t{0}, a.size() / 2, a.size() - 1}) {
    EXPECT_NEAR(e[i]["alt_amsl_m"].get<double>(), a[i]["alt_amsl_m"].get<double>(), 1e-6) << "sample " << i;
    EXPECT_NEAR(e[i]["lat_deg"].get<double>(), a[i]["lat_deg"].get<double>(), 1e-9) << "sample " << i;
  }
  EXPECT_NEAR(e.front()["alt_amsl_m"].get<double>(), kFrom.alt_amsl_m, 1e-6);
  EXPECT_NEAR(e.back()["alt_amsl_m"].get<double>(), kTo.alt_amsl_m, 1e-6);
  // Without the conversion the same numbers fly the undulation higher.
  EXPECT_NEAR(u.front()["alt_amsl_m"].get<double>(), kFrom.alt_amsl_m + from_n_m_, 1e-6);
}

TEST_F(HeightRefCli, MissionFileNamesItsHeightReference) {
  nlohmann::json mission = {
      {"height_ref", "ellipsoid"},
      {"begin", {{"lat_deg", kFrom.lat_deg}, {"lon_deg", kFrom.lon_deg}, {"alt_amsl_m", kFrom.alt_amsl_m + from_n_m_}}},
      {"points", nlohmann::json::array()},
      {"end", {{"lat_deg", kTo.lat_deg}, {"lon_deg", kTo.lon_deg}, {"alt_amsl_m", kTo.alt_amsl_m + to_n_m_}}}};
  const std::string file = (dir_ / "mission.json").string();
  std::ofstream(file) << mission.dump();

  const auto planned = runCli("plan --mission " + file + common("file.json"));
  ASSERT_EQ(planned.exit_code, 0) << planned.text;
  const nlohmann::json s = samples("file.json");
  ASSERT_FALSE(s.empty());
  EXPECT_NEAR(s.front()["alt_amsl_m"].get<double>(), kFrom.alt_amsl_m, 1e-6);
  EXPECT_NEAR(s.back()["alt_amsl_m"].get<double>(), kTo.alt_amsl_m, 1e-6);

  // The option may repeat the file's reference, never contradict it.
  const auto agreeing = runCli("plan --mission " + file + " --height-ref ellipsoid" + common("agree.json"));
  EXPECT_EQ(agreeing.exit_code, 0) << agreeing.text;
  const auto contradicting = runCli("plan --mission " + file + " --height-ref amsl" + common("x.json"));
  EXPECT_EQ(contradicting.exit_code, 2) << contradicting.text;
  EXPECT_NE(contradicting.text.find("--height-ref amsl disagrees with the mission file's height_ref ellipsoid"),
            std::string::npos)
      << contradicting.text;

  mission["height_ref"] = "geoid";
  std::ofstream(file) << mission.dump();
  const auto bad_field = runCli("plan --mission " + file + common("y.json"));
  EXPECT_EQ(bad_field.exit_code, 3) << bad_field.text;
  EXPECT_NE(bad_field.text.find("height_ref \"geoid\" is not a height reference"), std::string::npos) << bad_field.text;
}

TEST_F(HeightRefCli, BadValuesAreUsageErrorsNamingTheOption) {
  const std::string points = " --from " + triple(kFrom, 1100) + " --to " + triple(kTo, 1100);
  const auto unknown = runCli("plan --height-ref geoid" + points + common("z.json"));
  EXPECT_EQ(unknown.exit_code, 2) << unknown.text;
  EXPECT_NE(unknown.text.find("--height-ref"), std::string::npos) << unknown.text;
  EXPECT_NE(unknown.text.find("'geoid' is not a height reference: use amsl or ellipsoid"), std::string::npos)
      << unknown.text;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "z.json"));

  // ENU points carry AMSL already: an ellipsoidal reference for them is a mistake, named.
  const auto enu = runCli("plan --height-ref ellipsoid --mission " +
                          testing::projectDataPath("missions/demo_mission.json") + common("w.json"));
  EXPECT_EQ(enu.exit_code, 2) << enu.text;
  EXPECT_NE(enu.text.find("--height-ref ellipsoid: begin: the point is given in ENU metres"), std::string::npos)
      << enu.text;
}

}  // namespace
}  // namespace skyroute
