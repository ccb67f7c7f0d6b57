#include "tests/test_data.hpp"

#include <cstdlib>
#include <filesystem>

namespace skyroute::testing {

std::string sharedDataPath(const std::string& relative) {
  const std::string path = std::string(SKYROUTE_SHARED_DATA_DIR) + "/" + relative;
  return std::filesystem::exists(path) ? path : std::string();
}

std::string projectDataPath(const std::string& relative) {
  return std::string(SKYROUTE_DATA_DIR) + "/" + relative;
}

bool sharedDataRequired() {
  const char* value = std::getenv("SKYROUTE_REQUIRE_DATA");
  return value != nullptr && *value != '\0' && std::string(value) != "0";
}

std::string missingSharedData(const std::string& relative) {
  return "shared data " + relative + " not found under " + SKYROUTE_SHARED_DATA_DIR +
         (sharedDataRequired() ? " (SKYROUTE_REQUIRE_DATA is set: a missing file fails the test)"
                               : " (../shared/data is absent in a fresh clone; SKYROUTE_REQUIRE_DATA=1 makes this a failure)");
}

}  // namespace skyroute::testing
