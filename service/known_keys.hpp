// Unknown keys in what a user writes: every reader of a JSON input (mission and fleet files,
// obstacle feeds, no-fly zones) and the daemon's TOML configuration refuses a key it does not
// know, naming the key, where it is and the known key it most likely misspells, so a typo is
// never silently ignored ("point" for "points" used to fly straight from begin to end).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "planning/core/result.hpp"

namespace skyroute {

using KnownKeys = std::vector<std::string_view>;

// The known key `key` most likely misspells: the fewest edits (insert, delete, replace, swap two
// neighbours; case ignored) to the key or to the key without its unit suffix ("lat" for
// "lat_deg"), at most 1 + a third of the key's length; ties go to the earlier known key.
// nullopt when none is that close.
std::optional<std::string_view> closestKnownKey(std::string_view key, const KnownKeys& known);

// `unknown key "point" in mission (did you mean "points"?)`; without a close key, the known keys
// are listed: `unknown key "zz" in limits (known keys: model, v_ref_mps, ...)`.
std::string unknownKeyMessage(std::string_view key, std::string_view where, const KnownKeys& known);

// The first key of `object` (in key order) that is not in `known`, as a kParseError whose field
// is the key's path ("points[2].lat", or "point" when `path` is empty) and whose message is
// unknownKeyMessage with `where` (the object's path, or a name for a document's top level, e.g.
// "mission"). Nothing when every key is known or `object` is not an object (the reader refuses
// that itself, with its own message).
std::optional<Error> unknownJsonKey(const nlohmann::json& object, const KnownKeys& known, const std::string& path,
                                    const std::string& where);

}  // namespace skyroute
