// What a benchmark does when a case needs ../shared/data that is not there: it leaves the case
// out with a note, or, when SKYROUTE_REQUIRE_DATA is set (and not "0"; CI sets it), it stops with
// exit status 1, so a run cannot look complete while it skipped the real-data cases.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

namespace skyroute::bench {

inline bool sharedDataRequired() {
  const char* value = std::getenv("SKYROUTE_REQUIRE_DATA");
  return value != nullptr && *value != '\0' && std::string(value) != "0";
}

// `note` is printed as it is (it may be a table row); `why` names the file or the error.
inline void skipCaseForMissingData(const std::string& note, const std::string& why) {
  if (sharedDataRequired()) {
    std::fprintf(stderr, "shared data missing (SKYROUTE_REQUIRE_DATA is set): %s\n", why.c_str());
    std::exit(1);
  }
  std::printf("%s\n", note.c_str());
}

}  // namespace skyroute::bench
