#include "service/memory_guard.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

namespace skyroute {

std::optional<std::size_t> parseMemAvailable(const std::string& meminfo_text) {
  std::istringstream in(meminfo_text);
  std::string line;
  while (std::getline(in, line)) {
    unsigned long long kib = 0;
    if (std::sscanf(line.c_str(), "MemAvailable: %llu kB", &kib) == 1) return static_cast<std::size_t>(kib) * 1024;
  }
  return std::nullopt;
}

std::optional<std::size_t> availableMemoryBytes() {
  std::ifstream in("/proc/meminfo");
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return parseMemAvailable(text.str());
}

std::string bytesText(std::size_t bytes) {
  char buf[32];
  const double mib = static_cast<double>(bytes) / (1024.0 * 1024.0);
  if (mib < 1024.0) {
    std::snprintf(buf, sizeof buf, "%.0f MiB", mib);
  } else {
    std::snprintf(buf, sizeof buf, "%.1f GiB", mib / 1024.0);
  }
  return buf;
}

Status checkMemoryEstimate(std::size_t estimate_bytes, std::size_t limit_bytes, const std::string& limit_source,
                           const std::string& option, const std::string& what) {
  if (estimate_bytes <= limit_bytes) return Status::success();
  return make_error(ErrorCode::kInvalidArgument, option,
                    what + " would take about " + bytesText(estimate_bytes) + ", more than the " +
                        bytesText(limit_bytes) + " this machine can spare (" + limit_source + ")");
}

}  // namespace skyroute
