// The text bounds themselves (service/text_bounds.hpp): what an id, a name and free text may
// hold, and how a refused string is echoed.
#include <gtest/gtest.h>

#include <string>

#include "service/text_bounds.hpp"

namespace skyroute {
namespace {

TEST(TextBounds, AnIdIsOneToSixtyFourCharactersOfItsSet) {
  for (const char* id : {"uav-1", "UAV_7", "_x", "a.b-c_d", "7"}) EXPECT_TRUE(isValidId(id)) << id;
  EXPECT_TRUE(isValidId(std::string(64, 'a')));
  EXPECT_FALSE(isValidId(std::string(65, 'a')));
  for (const char* id : {"", "-uav", ".uav", "uav 1", "uav,1", "uav\n1", "=1+1", "uav/1", "uav\"1", "ü"})
    EXPECT_FALSE(isValidId(id)) << id;
  EXPECT_TRUE(isValidId(std::string(128, 'r'), kMaxRequestIdChars));
}

TEST(TextBounds, ARefusalNamesTheFieldTheLengthAndTheFirstBadCharacter) {
  auto missing = checkId("", "vehicle_id");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->field, "vehicle_id");
  EXPECT_EQ(missing->message, "vehicle_id is missing (empty)");
  EXPECT_FALSE(checkOptionalId("", "vehicle_id"));

  auto too_long = checkId(std::string(70000, 'a'), "vehicle_id");
  ASSERT_TRUE(too_long);
  EXPECT_NE(too_long->message.find("has 70000 characters, more than the limit of 64"), std::string::npos);
  EXPECT_LT(too_long->message.size(), 300u) << too_long->message;

  auto newline = checkId("uav\nevent=x", "vehicle_id");
  ASSERT_TRUE(newline);
  EXPECT_NE(newline->message.find("0x0a at position 3"), std::string::npos) << newline->message;
  EXPECT_EQ(newline->message.find('\n'), std::string::npos) << "the message itself forges a line";
}

TEST(TextBounds, NamesAreShortPrintableAsciiAndFreeTextHasNoControlCharacters) {
  EXPECT_FALSE(checkName("rrt-star", "planner"));
  EXPECT_FALSE(checkName("", "planner"));
  EXPECT_TRUE(checkName(std::string(65, 'p'), "planner"));
  EXPECT_TRUE(checkName("rrt\x1b[2J", "planner"));
  EXPECT_FALSE(checkFreeText("a reason,\twith a tab", "message"));
  EXPECT_TRUE(checkFreeText("two\nlines", "message"));
  EXPECT_TRUE(checkFreeText(std::string(kMaxFreeTextBytes + 1, 'm'), "message"));
}

TEST(TextBounds, AnEchoIsShortAndSafeAndBoundedTextKeepsWholeCharacters) {
  EXPECT_EQ(echoOfUntrusted("uav-1"), "uav-1");
  EXPECT_EQ(echoOfUntrusted("uav 1\n"), "uav?1?");
  EXPECT_EQ(echoOfUntrusted(std::string(70000, 'a')), std::string(64, 'a') + "...(70000 characters)");
  EXPECT_EQ(boundedFreeText("line\none"), "line?one");
  // "é" is two bytes: a cut between them keeps neither.
  const std::string accented = std::string(kMaxFreeTextBytes - 1, 'x') + "\xc3\xa9";
  EXPECT_EQ(boundedFreeText(accented), std::string(kMaxFreeTextBytes - 1, 'x'));
  EXPECT_EQ(boundedFreeText(std::string(kMaxFreeTextBytes + 10, 'y')).size(), kMaxFreeTextBytes);
}

}  // namespace
}  // namespace skyroute
