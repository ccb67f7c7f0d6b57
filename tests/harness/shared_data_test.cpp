// The rule of tests/test_data.hpp itself: a test whose shared data is missing fails, naming the
// file and where it was looked for, when SKYROUTE_REQUIRE_DATA is set (as CI sets it), so a machine
// without ../shared/data cannot pass the suite by skipping.
#include <cstdlib>
#include <string>

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include "tests/test_data.hpp"

namespace skyroute {
namespace {

void requireMissingFile() {
  SKYROUTE_REQUIRE_SHARED(path, "no/such/file.map");
  FAIL() << "a missing file was found: " << path;
}

// Sets an environment variable for one scope and puts the old value back.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value, 1);
  }
  ~ScopedEnv() {
    if (old_.empty()) ::unsetenv(name_);
    else ::setenv(name_, old_.c_str(), 1);
  }

 private:
  const char* name_;
  std::string old_;
};

TEST(SharedData, MissingFileFailsWhenRequired) {
  const ScopedEnv required("SKYROUTE_REQUIRE_DATA", "1");
  EXPECT_TRUE(testing::sharedDataRequired());
  EXPECT_FATAL_FAILURE(requireMissingFile(), "no/such/file.map not found under");
}

TEST(SharedData, OnlyAnExplicitZeroOrNothingLetsMissingDataSkip) {
  {
    const ScopedEnv off("SKYROUTE_REQUIRE_DATA", "0");
    EXPECT_FALSE(testing::sharedDataRequired());
  }
  {
    const ScopedEnv empty("SKYROUTE_REQUIRE_DATA", "");
    EXPECT_FALSE(testing::sharedDataRequired());
  }
  const ScopedEnv yes("SKYROUTE_REQUIRE_DATA", "yes");
  EXPECT_TRUE(testing::sharedDataRequired());
}

}  // namespace
}  // namespace skyroute
