// A guard in front of the TOML library. Debian's toml++ 3.3 reaches undefined behaviour (an
// "unreachable" branch in its Unicode tables) whenever it asks whether certain non-ASCII characters
// are whitespace or end a value: U+00A1..U+0499, U+2C8E..U+3087 and U+FC06..U+FEFE, which include
// everyday letters such as 'ä'. It asks that of every character outside strings and comments, of
// the characters a bare value's look-ahead reads, and of those after a backslash in a multi-line
// basic string. All were found by the config fuzzer (docs/fuzzing.md).
//
// findTomlHazard walks the document with TOML's own structure (keys, values, arrays, inline
// tables, strings, comments) and refuses, with line and column, every place where the library
// would ask: non-ASCII text is accepted only inside strings and comments.
#pragma once

#include <optional>
#include <string>

#include "planning/core/result.hpp"

namespace skyroute {

// nullopt when toml++ may parse `toml_text`; otherwise a kParseError whose message reads
// "<source_name>:<line>:<column>: <reason>".
std::optional<Error> findTomlHazard(const std::string& toml_text, const std::string& source_name);

}  // namespace skyroute
