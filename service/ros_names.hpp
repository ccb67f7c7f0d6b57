// ROS 2 names for skyroute's vehicle ids. A ROS name allows only [A-Za-z0-9_/], and no token
// (the parts between '/') may be empty or start with a digit. A vehicle id that is already such a
// name is used as it is; any other is sanitised: every other character becomes '_', empty tokens
// are dropped and a token that starts with a digit gets a leading '_' ("uav-1" -> "uav_1",
// "7/b" -> "_7/b").
//
// Two ids can sanitise to the same name ("uav-1" and "uav.1"). The registry gives every vehicle a
// name of its own, and never moves a vehicle whose id is a valid name: an id that had to be
// sanitised yields its name to the vehicle whose id it is, and a second sanitised id that lands on
// a taken name gets a suffix from a hash of its id ("uav_1_9f3c0a27"), the same on every run.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace skyroute {

// Whether text is a relative ROS name as skyroute uses one (no leading or trailing '/').
bool isValidRosName(std::string_view text);
std::string sanitiseRosName(std::string_view vehicle_id);

class RosNameRegistry {
 public:
  struct Assignment {
    std::string name;  // the vehicle's name
    // A vehicle that had to give its name up to this one, and its new name.
    std::optional<std::string> displaced_vehicle;
    std::string displaced_name;
  };

  // The vehicle's name, given the first time the vehicle is seen.
  Assignment assign(const std::string& vehicle_id);
  // The vehicle's name, if it has one.
  const std::string* nameOf(const std::string& vehicle_id) const;

 private:
  std::string hashedName(const std::string& vehicle_id) const;

  std::map<std::string, std::string> name_of_vehicle_;
  std::map<std::string, std::string> vehicle_of_name_;
};

}  // namespace skyroute
