#include "service/number_text.hpp"

#include <cstdio>

namespace skyroute {

std::string numberText(double value, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
  return buffer;
}

std::string enuText(const Eigen::Vector3d& p_m) {
  return "(" + numberText(p_m.x(), 7) + ", " + numberText(p_m.y(), 7) + ", " + numberText(p_m.z(), 7) + ") m ENU";
}

}  // namespace skyroute
