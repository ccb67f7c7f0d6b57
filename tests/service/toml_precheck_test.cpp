// The guard in front of toml++: valid TOML with non-ASCII text in strings and comments passes and
// parses; each place where the library would classify a non-ASCII character is refused with its
// line and column.
#include "service/toml_precheck.hpp"

#include <gtest/gtest.h>

#include <string>
#include <toml++/toml.h>

namespace skyroute {
namespace {

TEST(TomlPrecheck, ValidDocumentsWithNonAsciiTextPassAndParse) {
  const char* documents[] = {
      "# H\xC3\xB6he \xE3\x80\x80\n[dds]\nservice_id = \"s\xC3\xBC" "d\"  # \xC8\xA3\n",
      "[a.\"\xC3\xA4\"]\nb = '\xC8\xA3'\n[[c]]\nd = [\"\xC3\xA4\", '\xC3\xB6', \"\"\"\xC8\xA3\"\"\"]\n",
      "x = { a = \"\xC3\xA4\", b = [1, 2,], c = {} }\ny = []\n",
      "t = 1979-05-27 07:32:00Z\nu = \"\xC3\xA4\"\n",
      "m = \"\"\"\n\xC3\xA4\\\\\n\xC8\xA3\"\"\"\"\nn = '''\xC3\xA4\\\n\xC8\xA3'''\n",
      "arr = [\n  \"\xC3\xA4\",  # \xC3\xB6\n  2,\n]\nk = true\n",
      "\xEF\xBB\xBF" "a . b = \"\xC3\xA4\"\n",
  };
  for (const char* text : documents) {
    EXPECT_EQ(findTomlHazard(text, "ok.toml"), std::nullopt) << text;
    EXPECT_NO_THROW(toml::parse(text)) << text;
  }
}

TEST(TomlPrecheck, RefusesEachPlaceTheLibraryWouldClassifyNonAsciiText) {
  struct Case {
    std::string text;
    std::string where_and_why;
  };
  const Case cases[] = {
      {"[dds]\ndomin \xC3\xA4 6\n", "t.toml:2:7: a character outside a string"},
      {"x = 1.'\xC3\xA4'\n", "t.toml:1:8: a character outside a string"},
      {"peri=1='''\xC3\xA4'''\n", "t.toml:1:11: a character outside a string"},
      {"x = true\xC3\xA4\n", "t.toml:1:9: a character outside a string"},
      {"x = [1, \xC3\xA4]\n", "t.toml:1:9: a character outside a string"},
      {"x = \"\"\"in\\\xC8\xA3\"\"\"\n", "t.toml:1:11: a non-ASCII character after a backslash"},
      {"x = \"\"\"in\\ \n  \n \xC8\xA3\"\"\"\n", "t.toml:3:2: a non-ASCII character after a backslash"},
      {"x = \"a\" \"b\" \xC3\xA4\n", "t.toml:1:9: malformed TOML here, with non-ASCII text after it"},
      {"x = \"a\n\xC3\xA4 = 1\n", "t.toml:1:7: malformed TOML here"},
      {"# \xEF\xB9\xBF\n", "t.toml:1:3: character U+FE7F"},
      {"x = \"\xEF\xB0\x86\"\n", "t.toml:1:6: character U+FC06"},
  };
  for (const Case& c : cases) {
    const auto hazard = findTomlHazard(c.text, "t.toml");
    ASSERT_TRUE(hazard.has_value()) << c.text;
    EXPECT_EQ(hazard->code, ErrorCode::kParseError);
    EXPECT_EQ(hazard->field, "t.toml");
    EXPECT_EQ(hazard->message.rfind(c.where_and_why, 0), 0u) << c.text << " -> " << hazard->message;
  }
}

TEST(TomlPrecheck, MalformedAsciiIsLeftToTheLibrary) {
  // Without non-ASCII text after it a syntax error is the library's to report, with its wording.
  EXPECT_EQ(findTomlHazard("x = \"a\" \"b\"\n[planning\nseed = 1\n", "t.toml"), std::nullopt);
  EXPECT_EQ(findTomlHazard("= = = ]]] {{{ '''", "t.toml"), std::nullopt);
}

}  // namespace
}  // namespace skyroute
