// Numbers in messages and logs, %g-style: `digits` significant digits in the shorter of fixed and
// exponent notation, so 1e308 reads "1e+308" (never a 309-digit integer) and 0.25 reads "0.25".
#pragma once

#include <string>

#include <Eigen/Core>

namespace skyroute {

std::string numberText(double value, int digits = 6);

// "(east, north, up) m ENU" with 0.1 m resolution inside a 1000 km frame (7 significant digits).
std::string enuText(const Eigen::Vector3d& p_m);

}  // namespace skyroute
