// A whole text file as a string, for tests that compare what a command or writer produced.
#pragma once

#include <fstream>
#include <sstream>
#include <string>

namespace skyroute::testing {

// The file's contents; "" when it cannot be read.
inline std::string readTextFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace skyroute::testing
