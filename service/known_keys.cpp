#include "service/known_keys.hpp"

#include <algorithm>
#include <cctype>
#include <tuple>

#include <nlohmann/json.hpp>

namespace skyroute {
namespace {

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// Optimal string alignment distance: insertions, deletions, replacements and swaps of two
// neighbouring characters ("ordr" -> "order" is 1, "lenght" -> "length" is 1).
std::size_t editDistance(const std::string& a, const std::string& b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[n][m];
}

// The key without its last "_part" ("lat_deg" -> "lat", "size_m" -> "size"); itself without one.
std::string_view stem(std::string_view key) {
  const std::size_t underscore = key.rfind('_');
  return underscore == std::string_view::npos || underscore == 0 ? key : key.substr(0, underscore);
}

// The key as a JSON string: quotes, control characters and bad UTF-8 escaped or replaced, so a
// key cannot break the message's line; at most 64 characters of it.
std::string quoted(std::string_view text) {
  constexpr std::size_t kShownChars = 64;
  const bool cut = text.size() > kShownChars;
  const std::string shown = nlohmann::json(std::string(text.substr(0, kShownChars)))
                                .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return cut ? shown.substr(0, shown.size() - 1) + "...\"" : shown;
}

}  // namespace

std::optional<std::string_view> closestKnownKey(std::string_view key, const KnownKeys& known) {
  // A key read from a file may be any length: beyond any known key's length plus the allowance
  // no known key can be close, and the distance table stays small.
  constexpr std::size_t kLongestComparedKey = 256;
  if (key.size() > kLongestComparedKey) return std::nullopt;
  const std::string wanted = lower(key);
  const std::size_t allowed = 1 + key.size() / 3;
  std::optional<std::string_view> best;
  std::tuple<std::size_t, std::size_t> best_score{allowed + 1, 0};
  for (std::string_view candidate : known) {
    const std::size_t whole = editDistance(wanted, lower(candidate));
    const std::size_t score = std::min(whole, editDistance(wanted, lower(stem(candidate))));
    const std::tuple<std::size_t, std::size_t> this_score{score, whole};
    if (score <= allowed && this_score < best_score) {
      best = candidate;
      best_score = this_score;
    }
  }
  return best;
}

std::string unknownKeyMessage(std::string_view key, std::string_view where, const KnownKeys& known) {
  std::string message = "unknown key " + quoted(key) + " in " + std::string(where);
  if (auto close = closestKnownKey(key, known)) return message + " (did you mean " + quoted(*close) + "?)";
  std::string list;
  for (std::string_view k : known) list += (list.empty() ? "" : ", ") + std::string(k);
  return message + " (known keys: " + list + ")";
}

std::optional<Error> unknownJsonKey(const nlohmann::json& object, const KnownKeys& known, const std::string& path,
                                    const std::string& where) {
  if (!object.is_object()) return std::nullopt;
  for (const auto& [key, value] : object.items()) {
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    // An empty key ("": 1 is valid JSON) is named as written, so the field is never empty.
    const std::string name = key.empty() ? "\"\"" : key;
    return make_error(ErrorCode::kParseError, path.empty() ? name : path + "." + name,
                      unknownKeyMessage(key, where, known));
  }
  return std::nullopt;
}

}  // namespace skyroute
