// The identity-folder checks that run before a secured participant is created: a folder made by
// scripts/make-pki.sh passes; a missing file, another authority's certificate and a key of another
// identity are refused naming the file.
#include "service/dds/dds_security.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "tests/test_data.hpp"

namespace skyroute::dds {
namespace {

namespace fs = std::filesystem;

class SecurityFolder : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = (fs::temp_directory_path() / ("skyroute_security_folder_" + std::to_string(::getpid()))).string();
    fs::remove_all(root_);
    const std::string script = testing::projectDataPath("../scripts/make-pki.sh");
    made_ = std::system(("bash " + script + " " + root_ + "/a --days 1 > /dev/null && bash " + script + " " + root_ +
                         "/b --days 1 --cn-prefix other > /dev/null")
                            .c_str());
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  void SetUp() override { ASSERT_EQ(made_, 0); }

  // A copy of identity folder `from` as `name`, to spoil.
  static std::string copyOf(const std::string& from, const std::string& name) {
    const std::string to = root_ + "/" + name;
    fs::remove_all(to);
    fs::copy(root_ + "/" + from, to);
    return to;
  }

  static inline std::string root_;
  static inline int made_ = -1;
};

TEST_F(SecurityFolder, MadeFoldersPass) {
  for (const char* who : {"a/daemon", "a/station", "a/observer", "b/station"}) {
    const Status s = checkSecurityFolder(root_ + "/" + who);
    EXPECT_TRUE(s.ok()) << who << ": " << s.error().describe();
  }
}

// The folder's check fails, naming `file` of the folder, with `reason` in its message.
void expectRefused(const std::string& dir, const std::string& file, const std::string& reason) {
  const Status s = checkSecurityFolder(dir);
  ASSERT_FALSE(s.ok()) << dir;
  EXPECT_EQ(s.error().field, dir + "/" + file);
  EXPECT_NE(s.error().message.find(reason), std::string::npos) << s.error().message;
}

TEST_F(SecurityFolder, MissingFileIsNamed) {
  const std::string dir = copyOf("a/station", "missing");
  fs::remove(dir + "/permissions.p7s");
  expectRefused(dir, "permissions.p7s", "make-pki.sh");
}

TEST_F(SecurityFolder, AnotherAuthoritysCertificateIsRefused) {
  const std::string dir = copyOf("a/station", "foreign");
  for (const char* file : {"identity.pem", "identity.key"}) {
    fs::copy_file(root_ + "/b/station/" + file, dir + "/" + file, fs::copy_options::overwrite_existing);
  }
  expectRefused(dir, "identity.pem", "not signed by");
}

TEST_F(SecurityFolder, KeyOfAnotherIdentityIsRefused) {
  const std::string dir = copyOf("a/station", "wrong_key");
  fs::copy_file(root_ + "/a/observer/identity.key", dir + "/identity.key", fs::copy_options::overwrite_existing);
  expectRefused(dir, "identity.key", "is not the key of");
}

TEST_F(SecurityFolder, TextThatIsNoCertificateIsRefused) {
  const std::string dir = copyOf("a/station", "garbage");
  std::ofstream(dir + "/identity_ca.pem") << "not a certificate\n";
  expectRefused(dir, "identity_ca.pem", "is not a PEM certificate");
}

}  // namespace
}  // namespace skyroute::dds
