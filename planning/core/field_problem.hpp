// How every error of the project names its input in one line.
#pragma once

#include <string>

namespace skyroute {

// "field: message", or just message when field is empty.
std::string describeFieldProblem(const std::string& field, const std::string& message);

}  // namespace skyroute
