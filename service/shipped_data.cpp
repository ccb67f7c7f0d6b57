#include "service/shipped_data.hpp"

#include <filesystem>
#include <system_error>

namespace skyroute {

namespace {

std::filesystem::path runningBinary() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : exe;
}

// The existing <dir>/<relative>, or "" with the folders searched in `searched`.
std::string firstExisting(const std::string& relative, const std::string& exe_path, std::string& searched) {
  const std::vector<std::string> dirs = shippedDataDirs(exe_path);
  searched.clear();
  for (const std::string& dir : dirs) {
    const std::filesystem::path candidate = std::filesystem::path(dir) / relative;
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec)) return candidate.string();
    searched += (searched.empty() ? "" : ", ") + dir;
  }
  if (dirs.empty()) searched = "nowhere: /proc/self/exe does not name this binary";
  return "";
}

}  // namespace

std::vector<std::string> shippedDataDirs(const std::string& exe_path) {
  const std::filesystem::path exe = exe_path.empty() ? runningBinary() : std::filesystem::path(exe_path);
  if (exe.empty()) return {};
  // <prefix>/bin/skyroute -> <prefix>/share/skyroute, spelled without "..", so messages show
  // the folder a user would look in.
  return {(exe.parent_path().parent_path() / "share" / "skyroute").lexically_normal().string()};
}

Result<std::string> findShippedData(const std::string& relative, const std::string& exe_path) {
  std::string searched;
  std::string found = firstExisting(relative, exe_path, searched);
  if (!found.empty()) return found;
  return make_error(ErrorCode::kFileNotFound, relative,
                    "the shipped data file " + relative + " was not found; searched " + searched +
                        " (share/skyroute beside the binary's folder)");
}

Result<std::string> defaultTerrainPath(const std::string& exe_path) {
  std::string searched;
  std::string found = firstExisting(kDefaultTerrainFile, exe_path, searched);
  if (!found.empty()) return found;
  return make_error(ErrorCode::kFileNotFound, "terrain.dem",
                    std::string("no DEM given, and the embedded default terrain ") + kDefaultTerrainFile +
                        " was not found; searched " + searched +
                        " (share/skyroute beside the binary's folder): reinstall skyroute's data there, or "
                        "give --dem FILE (terrain.dem in the configuration)");
}

}  // namespace skyroute
