// Vehicle ids as ROS 2 names: valid names stay as they are, others are sanitised by the documented
// rule, and two ids never share a name, whatever order they come in.
#include <gtest/gtest.h>

#include "service/ros_names.hpp"

namespace skyroute {
namespace {

TEST(RosNames, ValidNamesFollowTheRosRules) {
  for (const char* ok : {"uav_1", "UAV1", "_1", "fleet/uav_2", "a/b/c"}) EXPECT_TRUE(isValidRosName(ok)) << ok;
  for (const char* bad : {"", "uav-1", "1uav", "fleet/2", "/uav", "uav/", "a//b", "uav 1", "uav.1", "ü"}) {
    EXPECT_FALSE(isValidRosName(bad)) << bad;
  }
}

TEST(RosNames, SanitisingGivesAValidNameAndKeepsValidOnes) {
  EXPECT_EQ(sanitiseRosName("uav_1"), "uav_1");
  EXPECT_EQ(sanitiseRosName("uav-1"), "uav_1");
  EXPECT_EQ(sanitiseRosName("uav.1"), "uav_1");
  EXPECT_EQ(sanitiseRosName("7"), "_7");
  EXPECT_EQ(sanitiseRosName("/fleet//2/"), "fleet/_2");
  EXPECT_EQ(sanitiseRosName("---"), "___");
  EXPECT_EQ(sanitiseRosName("//"), "_");
  for (const char* id : {"uav-1", "7", "/fleet//2/", "a b", "ü", "//", "x/-/y"}) {
    EXPECT_TRUE(isValidRosName(sanitiseRosName(id))) << id << " -> " << sanitiseRosName(id);
  }
}

TEST(RosNames, TwoIdsThatSanitiseAlikeGetDifferentStableNames) {
  RosNameRegistry names;
  EXPECT_EQ(names.assign("uav-1").name, "uav_1");
  const RosNameRegistry::Assignment second = names.assign("uav.1");
  EXPECT_NE(second.name, "uav_1");
  EXPECT_EQ(second.name.rfind("uav_1_", 0), 0u) << second.name;
  EXPECT_EQ(second.name.size(), std::string("uav_1_").size() + 8);  // 8 hex digits
  EXPECT_TRUE(isValidRosName(second.name));
  EXPECT_FALSE(second.displaced_vehicle);
  EXPECT_EQ(names.assign("uav-1").name, "uav_1");  // asking again changes nothing
  // The suffix is a hash of the id: the same on every run and in every daemon.
  RosNameRegistry other;
  (void)other.assign("uav_1");
  EXPECT_EQ(other.assign("uav.1").name, second.name);
}

TEST(RosNames, AVehicleWhoseIdIsTheNameTakesItFromASanitisedOne) {
  RosNameRegistry names;
  EXPECT_EQ(names.assign("uav-1").name, "uav_1");
  const RosNameRegistry::Assignment own = names.assign("uav_1");
  EXPECT_EQ(own.name, "uav_1");
  ASSERT_TRUE(own.displaced_vehicle);
  EXPECT_EQ(*own.displaced_vehicle, "uav-1");
  EXPECT_EQ(own.displaced_name.rfind("uav_1_", 0), 0u);
  ASSERT_NE(names.nameOf("uav-1"), nullptr);
  EXPECT_EQ(*names.nameOf("uav-1"), own.displaced_name);
  EXPECT_EQ(*names.nameOf("uav_1"), "uav_1");

  // In the other order nobody moves, and the names come out the same.
  RosNameRegistry reversed;
  EXPECT_EQ(reversed.assign("uav_1").name, "uav_1");
  const RosNameRegistry::Assignment late = reversed.assign("uav-1");
  EXPECT_FALSE(late.displaced_vehicle);
  EXPECT_EQ(late.name, own.displaced_name);
}

}  // namespace
}  // namespace skyroute
