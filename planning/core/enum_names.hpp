// An enum's text names, listed once in a table that serves both directions: to_string reads a
// value's name, parsing reads the value a name stands for.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>

namespace skyroute {

template <class Enum>
struct EnumName {
  Enum value;
  std::string_view name;
};

// The value's name; `unknown` for a value the table lacks (one cast from an out-of-range int).
template <class Enum, std::size_t N>
constexpr std::string_view enumName(const EnumName<Enum> (&names)[N], Enum value,
                                    std::string_view unknown = "unknown") {
  for (const EnumName<Enum>& entry : names)
    if (entry.value == value) return entry.name;
  return unknown;
}

// The value with this exact name; nullopt for any other text.
template <class Enum, std::size_t N>
constexpr std::optional<Enum> enumNamed(const EnumName<Enum> (&names)[N], std::string_view name) {
  for (const EnumName<Enum>& entry : names)
    if (entry.name == name) return entry.value;
  return std::nullopt;
}

}  // namespace skyroute
