// Named derivative orders (as mav_trajectory_generation does), so call sites say what they ask for
// instead of passing a bare integer.
#pragma once

#include <string_view>

namespace skyroute {

enum class Derivative : int {
  kPosition = 0,      // m
  kVelocity = 1,      // m/s
  kAcceleration = 2,  // m/s^2
  kJerk = 3,          // m/s^3
  kSnap = 4,          // m/s^4
};

constexpr int order(Derivative d) { return static_cast<int>(d); }

constexpr std::string_view to_string(Derivative d) {
  switch (d) {
    case Derivative::kPosition: return "position";
    case Derivative::kVelocity: return "velocity";
    case Derivative::kAcceleration: return "acceleration";
    case Derivative::kJerk: return "jerk";
    case Derivative::kSnap: return "snap";
  }
  return "unknown";
}

}  // namespace skyroute
