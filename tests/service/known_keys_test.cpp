// The one key check of every JSON reader: which known key an unknown one most likely misspells,
// and the message and field that name it.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "service/known_keys.hpp"

namespace skyroute {
namespace {

const KnownKeys kMissionKeys{"request_id", "vehicle_id", "begin", "points", "end", "limits", "planner", "fixed_order"};

TEST(KnownKeys, TheClosestKnownKeyIsTheFewestEditsAwayCaseIgnored) {
  EXPECT_EQ(closestKnownKey("point", kMissionKeys), "points");
  EXPECT_EQ(closestKnownKey("vehicleId", kMissionKeys), "vehicle_id");
  EXPECT_EQ(closestKnownKey("fixed_ordr", kMissionKeys), "fixed_order");
  EXPECT_EQ(closestKnownKey("fxied_order", kMissionKeys), "fixed_order");  // two neighbours swapped: one edit
  EXPECT_EQ(closestKnownKey("PLANNER", kMissionKeys), "planner");
  // The unit suffix left out counts as close.
  EXPECT_EQ(closestKnownKey("lat", {"lat_deg", "lon_deg", "alt_amsl_m"}), "lat_deg");
  EXPECT_EQ(closestKnownKey("speed", {"velocity_mps", "speed_mps"}), "speed_mps");
  // Nothing close: no guess.
  EXPECT_EQ(closestKnownKey("comment", kMissionKeys), std::nullopt);
  EXPECT_EQ(closestKnownKey("", kMissionKeys), std::nullopt);
  EXPECT_EQ(closestKnownKey(std::string(100000, 'x'), kMissionKeys), std::nullopt);
}

TEST(KnownKeys, TheMessageNamesTheKeyWhereItIsAndTheClosestKeyOrTheKnownOnes) {
  EXPECT_EQ(unknownKeyMessage("point", "mission", kMissionKeys),
            "unknown key \"point\" in mission (did you mean \"points\"?)");
  EXPECT_EQ(unknownKeyMessage("zz", "limits", {"model", "v_ref_mps"}),
            "unknown key \"zz\" in limits (known keys: model, v_ref_mps)");
  // A key that would break the message's line is escaped, and a long one cut.
  EXPECT_EQ(unknownKeyMessage("a\nb\"", "x", {"y"}), "unknown key \"a\\nb\\\"\" in x (known keys: y)");
  const std::string long_message = unknownKeyMessage(std::string(70000, 'k'), "x", {"y"});
  EXPECT_LT(long_message.size(), 120u) << long_message;
  EXPECT_NE(long_message.find("kkk...\" in x"), std::string::npos) << long_message;
}

TEST(KnownKeys, TheErrorsFieldIsTheKeysPath) {
  const auto j = nlohmann::json::parse(R"({"east_m": 1, "nrth_m": 2})");
  const auto e = unknownJsonKey(j, {"east_m", "north_m", "up_m"}, "points[2]", "points[2]");
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->code, ErrorCode::kParseError);
  EXPECT_EQ(e->field, "points[2].nrth_m");
  EXPECT_EQ(e->message, "unknown key \"nrth_m\" in points[2] (did you mean \"north_m\"?)");
  EXPECT_EQ(unknownJsonKey(nlohmann::json::parse(R"({"": 1})"), kMissionKeys, "", "mission")->field, "\"\"");
  EXPECT_FALSE(unknownJsonKey(nlohmann::json::parse(R"({"end": 1})"), kMissionKeys, "", "mission"));
  EXPECT_FALSE(unknownJsonKey(nlohmann::json::array(), kMissionKeys, "", "mission"));  // not an object: the reader's
}

}  // namespace
}  // namespace skyroute
