// Event lines ("event=<name> key=value ...") become JSON fields for the json log format.
#include <gtest/gtest.h>

#include "service/logging.hpp"

namespace skyroute {
namespace {

TEST(LogEventFields, KeysValuesTypedAndQuotedValuesUnescaped) {
  const auto j = logEventFields(
      R"(event=plan_succeeded request=r-1 vehicle=uav-7 plan=uav-7-1 duration_s=299.4 samples=1498 ok=true )"
      R"(message="a \"quoted\" word = here")");
  EXPECT_EQ(j["event"], "plan_succeeded");
  EXPECT_EQ(j["request"], "r-1");
  EXPECT_EQ(j["vehicle"], "uav-7");
  ASSERT_TRUE(j["duration_s"].is_number_float());
  EXPECT_DOUBLE_EQ(j["duration_s"].get<double>(), 299.4);
  ASSERT_TRUE(j["samples"].is_number_integer());
  EXPECT_EQ(j["samples"].get<int>(), 1498);
  EXPECT_EQ(j["ok"], true);
  EXPECT_EQ(j["message"], "a \"quoted\" word = here");
  EXPECT_FALSE(j.contains("msg"));
  // The order of the line is kept.
  EXPECT_EQ(j.begin().key(), "event");
}

TEST(LogEventFields, FreeTextIsKeptAsMsg) {
  EXPECT_EQ(logEventFields("plain words, no fields")["msg"], "plain words, no fields");
  const auto j = logEventFields("event=x count=3 and then some words");
  EXPECT_EQ(j["event"], "x");
  EXPECT_EQ(j["count"], 3);
  EXPECT_EQ(j["msg"], "and then some words");
  // An id that looks partly numeric stays a string.
  EXPECT_EQ(logEventFields("event=y revision=2 request=12ab")["request"], "12ab");
  EXPECT_EQ(logEventFields("event=y unterminated=\"abc")["msg"], "event=y unterminated=\"abc");
}

}  // namespace
}  // namespace skyroute
