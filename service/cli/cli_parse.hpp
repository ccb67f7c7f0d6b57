// The command line's own helpers, free of the engine's types (the grid tools use them beside
// planning/'s): failing with the exit-code table, --help footers, parsing "LAT,LON,ALT", "X,Y" and
// ";"-separated lists, checking output paths before any work, reading JSON files.
#pragma once

#include <initializer_list>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "planning/core/result.hpp"
#include "service/cli/exit_codes.hpp"
#include "service/mission_types.hpp"
#include "service/number_text.hpp"  // numberText: numbers as --help and messages show them
#include "terrain/grid_layer.hpp"

namespace skyroute::cli {

// A --help footer: the examples, one a line, then the exit-code table.
std::string helpFooter(std::initializer_list<std::string> examples);

// "LAT,LON,ALT" in degrees and metres AMSL; field names the option in errors.
Result<MissionPointData> parseGeoTriple(const std::string& text, const std::string& field);
// "X,Y": a grid cell (column, row); field names the option in errors.
Result<GridCell> parseGridCell(const std::string& text, const std::string& field);
// The items of a list separated by ';', blanks around items trimmed, empty items dropped.
std::vector<std::string> splitList(const std::string& text);

// Each item of a ';'-separated list option through `parse`, named "option[i]" in errors; a bad
// item fails with kExitUsage.
template <class T>
std::vector<T> parseListOption(const std::string& tool, const std::string& option, const std::string& text,
                               Result<T> (*parse)(const std::string& item, const std::string& field)) {
  std::vector<T> values;
  const std::vector<std::string> items = splitList(text);
  for (std::size_t i = 0; i < items.size(); ++i) {
    auto value = parse(items[i], option + "[" + std::to_string(i) + "]");
    if (!value) fail(tool, kExitUsage, value.error().message);
    values.push_back(std::move(*value));
  }
  return values;
}

// The extension of a path, lower case, without the dot ("" when none).
std::string lowerExtension(const std::string& path);
// An output path, checked before any work: an extension among `formats` and a folder that exists.
// Fails with kExitUsage naming the option. An empty path passes (the output was not asked for).
void checkOutputPath(const std::string& tool, const std::string& option, const std::string& path,
                     const std::vector<std::string>& formats);
// A JSON file; fails with kExitBadInput naming the option and the file.
nlohmann::json readJsonFile(const std::string& tool, const std::string& option, const std::string& path);

}  // namespace skyroute::cli
