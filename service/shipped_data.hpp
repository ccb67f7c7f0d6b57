// Where the data skyroute ships (the embedded default terrain, the example missions and feeds)
// is found at run time: in share/skyroute beside the running binary's folder, found through
// /proc/self/exe, so an install works wherever its prefix is and a moved or copied tree keeps
// working. An install puts the binaries in <prefix>/bin and the data in <prefix>/share/skyroute;
// the build tree mirrors that with build/share/skyroute, a link to the checkout's data/.
#pragma once

#include <string>
#include <vector>

#include "planning/core/result.hpp"

namespace skyroute {

inline constexpr const char* kDefaultTerrainFile = "default_terrain.tif";

// The folders searched for shipped data, in order. exe_path is the running binary ("" = this
// process's /proc/self/exe).
std::vector<std::string> shippedDataDirs(const std::string& exe_path = "");

// The first existing <dir>/<relative> over shippedDataDirs(exe_path). Error kFileNotFound (field:
// the file's name) naming every folder searched.
Result<std::string> findShippedData(const std::string& relative, const std::string& exe_path = "");

// The embedded default terrain: what `--dem` and the configuration's terrain.dem default to.
// Error kFileNotFound (field "terrain.dem") naming every folder searched and how to go on.
Result<std::string> defaultTerrainPath(const std::string& exe_path = "");

}  // namespace skyroute
