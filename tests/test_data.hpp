// Where tests find data: the project's data/ (always there) and ../shared/data (CI has it, a fresh
// clone may not). Tests that need shared data call SKYROUTE_REQUIRE_SHARED: without the file they
// skip with a message, unless the environment sets SKYROUTE_REQUIRE_DATA=1 (CI does, in .ci/run),
// in which case they fail, so a missing data folder cannot pass as green.
#pragma once

#include <string>

#include <gtest/gtest.h>

namespace skyroute::testing {

// Absolute path of ../shared/data/<relative>, or "" when it is not there.
std::string sharedDataPath(const std::string& relative);
std::string projectDataPath(const std::string& relative);
// SKYROUTE_REQUIRE_DATA is set (and not "0"): missing shared data is a failure, not a skip.
bool sharedDataRequired();
// The message for a missing shared file, naming where it was looked for.
std::string missingSharedData(const std::string& relative);

}  // namespace skyroute::testing

// Skips the test (or fails it, under SKYROUTE_REQUIRE_DATA) when ../shared/data/<relative> is missing.
#define SKYROUTE_SKIP_OR_FAIL_MISSING(relative)                                                   \
  do {                                                                                            \
    if (::skyroute::testing::sharedDataRequired()) {                                              \
      GTEST_FAIL() << ::skyroute::testing::missingSharedData(relative);                           \
    } else {                                                                                      \
      GTEST_SKIP() << ::skyroute::testing::missingSharedData(relative);                           \
    }                                                                                             \
  } while (false)

// Declares `var` as the absolute path of ../shared/data/<relative>; returns from the test (skip or
// failure, as above) when the file is missing.
#define SKYROUTE_REQUIRE_SHARED(var, relative)                                                    \
  const std::string var = ::skyroute::testing::sharedDataPath(relative);                          \
  if (var.empty()) SKYROUTE_SKIP_OR_FAIL_MISSING(relative)
