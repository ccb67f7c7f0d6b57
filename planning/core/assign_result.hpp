// Field-by-field readers put each member's Result in place with one line:
//   if (auto e = assignResult(readMember(...), out.member)) return *e;
#pragma once

#include <optional>
#include <utility>

#include "planning/core/result.hpp"

namespace skyroute {

// Moves the result's value into member; the result's error when it has none (member untouched).
template <class T, class E>
std::optional<E> assignResult(Result<T, E> result, T& member) {
  if (!result) return result.error();
  member = std::move(*result);
  return std::nullopt;
}

}  // namespace skyroute
