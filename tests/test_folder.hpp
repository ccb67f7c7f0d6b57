// A fixture that gives each test its own empty folder, removed afterwards: ctest runs every test
// as its own process, in parallel.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>

namespace skyroute::testing {

class TestFolderTest : public ::testing::Test {
 protected:
  // prefix names the suite: the folder is <temp>/<prefix><test name>.
  explicit TestFolderTest(std::string prefix) : prefix_(std::move(prefix)) {}

  void SetUp() override {
    const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    dir_ = std::filesystem::path(::testing::TempDir()) / (prefix_ + test);
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace skyroute::testing
