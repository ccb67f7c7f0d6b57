// How a harness reports a finding: the harness and what went wrong on stderr, then abort, which
// libFuzzer records as a crash and keeps the input of.
#pragma once

#include <cstdlib>
#include <iostream>
#include <string>

namespace skyroute::fuzz {

[[noreturn]] inline void reportFinding(const char* harness, const std::string& what) {
  std::cerr << harness << ": " << what << std::endl;
  std::abort();
}

}  // namespace skyroute::fuzz
