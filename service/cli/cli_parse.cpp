#include "service/cli/cli_parse.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>

#include <CLI/CLI.hpp>

namespace skyroute::cli {

void fail(const std::string& tool, int code, const std::string& message) {
  std::cerr << "skyroute " << tool << ": " << message << std::endl;
  throw CLI::RuntimeError(code);
}

std::string helpFooter(std::initializer_list<std::string> examples) {
  std::string text = examples.size() == 1 ? "Example:\n" : "Examples:\n";
  for (const std::string& line : examples) text += "  " + line + "\n";
  return text + "\n" + std::string(kExitCodeTable);
}

Result<MissionPointData> parseGeoTriple(const std::string& text, const std::string& field) {
  double v[3];
  std::istringstream in(text);
  std::string part;
  int n = 0;
  while (std::getline(in, part, ',')) {
    if (n == 3) return make_error(ErrorCode::kParseError, field, field + " '" + text + "' has more than 3 numbers (LAT,LON,ALT)");
    try {
      std::size_t used = 0;
      v[n] = std::stod(part, &used);
      if (part.find_first_not_of(" \t", used) != std::string::npos) throw std::invalid_argument(part);
    } catch (const std::exception&) {
      return make_error(ErrorCode::kParseError, field, field + " '" + text + "': '" + part + "' is not a number");
    }
    if (!std::isfinite(v[n])) return make_error(ErrorCode::kParseError, field, field + " '" + text + "': not finite");
    ++n;
  }
  if (n != 3) return make_error(ErrorCode::kParseError, field, field + " '" + text + "' must be LAT,LON,ALT (3 numbers)");
  return MissionPointData::wgs84(v[0], v[1], v[2]);
}

Result<GridCell> parseGridCell(const std::string& text, const std::string& field) {
  static const std::regex pattern(R"(\s*(-?\d{1,9})\s*,\s*(-?\d{1,9})\s*)");
  std::smatch m;
  if (!std::regex_match(text, m, pattern)) {
    return make_error(ErrorCode::kParseError, field, field + " '" + text + "' is not a cell X,Y (two integers: column, row)");
  }
  return GridCell{std::stoi(m[1].str()), std::stoi(m[2].str())};
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ';')) {
    const auto first = item.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    items.push_back(item.substr(first, item.find_last_not_of(" \t") - first + 1));
  }
  return items;
}

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

void checkOutputPath(const std::string& tool, const std::string& option, const std::string& path,
                     const std::vector<std::string>& formats) {
  if (path.empty()) return;
  const std::string ext = lowerExtension(path);
  if (std::find(formats.begin(), formats.end(), ext) == formats.end()) {
    std::string known;
    for (const auto& f : formats) known += (known.empty() ? "." : ", .") + f;
    fail(tool, kExitUsage, option + " " + path + ": unknown format '." + ext + "' (use " + known + ")");
  }
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  if (!folder.empty() && !std::filesystem::is_directory(folder)) {
    fail(tool, kExitUsage, option + " " + path + ": the folder " + folder.string() + " does not exist");
  }
}

nlohmann::json readJsonFile(const std::string& tool, const std::string& option, const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(tool, kExitBadInput, option + " " + path + ": cannot open the file");
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) fail(tool, kExitBadInput, option + " " + path + ": not valid JSON");
  return j;
}

}  // namespace skyroute::cli
