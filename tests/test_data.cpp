#include "tests/test_data.hpp"

#include <filesystem>

namespace skyroute::testing {

std::string sharedDataPath(const std::string& relative) {
  const std::string path = std::string(SKYROUTE_SHARED_DATA_DIR) + "/" + relative;
  return std::filesystem::exists(path) ? path : std::string();
}

std::string projectDataPath(const std::string& relative) {
  return std::string(SKYROUTE_DATA_DIR) + "/" + relative;
}

}  // namespace skyroute::testing
