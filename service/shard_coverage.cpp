#include "service/shard_coverage.hpp"

#include <algorithm>
#include <charconv>

namespace skyroute {

bool coversArrival(std::int64_t started_utc_ns, const std::vector<CoverageInterval>& past,
                   std::int64_t arrived_utc_ns, std::int64_t join_margin_ns) {
  if (started_utc_ns + join_margin_ns <= arrived_utc_ns) return true;
  return std::any_of(past.begin(), past.end(), [&](const CoverageInterval& life) {
    return life.started_utc_ns + join_margin_ns <= arrived_utc_ns && arrived_utc_ns <= life.covered_until_utc_ns;
  });
}

std::vector<CoverageInterval> advertisedCoverage(std::vector<CoverageInterval> lives, std::int64_t join_margin_ns) {
  std::erase_if(lives, [&](const CoverageInterval& life) {
    return life.covered_until_utc_ns < life.started_utc_ns + join_margin_ns;
  });
  std::sort(lives.begin(), lives.end(),
            [](const CoverageInterval& a, const CoverageInterval& b) { return a.started_utc_ns < b.started_utc_ns; });
  if (lives.size() > kMaxPastCoverage) lives.erase(lives.begin(), lives.end() - kMaxPastCoverage);
  return lives;
}

std::string coverageText(const std::vector<CoverageInterval>& past) {
  std::string out;
  for (const CoverageInterval& life : past) {
    if (!out.empty()) out += ',';
    out += std::to_string(life.started_utc_ns) + '-' + std::to_string(life.covered_until_utc_ns);
  }
  return out;
}

std::optional<std::vector<CoverageInterval>> coverageFromText(std::string_view text) {
  std::vector<CoverageInterval> out;
  if (text.empty()) return out;
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t end = std::min(text.find(',', at), text.size());
    const std::string_view item = text.substr(at, end - at);
    const std::size_t dash = item.find('-');
    if (dash == std::string_view::npos || out.size() >= kMaxPastCoverage) return std::nullopt;
    CoverageInterval life;
    const auto parse = [](std::string_view digits, std::int64_t& value) {
      const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
      return ec == std::errc() && ptr == digits.data() + digits.size() && !digits.empty();
    };
    if (!parse(item.substr(0, dash), life.started_utc_ns) || !parse(item.substr(dash + 1), life.covered_until_utc_ns)) {
      return std::nullopt;
    }
    out.push_back(life);
    at = end + 1;
  }
  return out;
}

}  // namespace skyroute
