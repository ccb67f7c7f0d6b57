// Typed errors and a small Result<T> (value or Error) used by every layer.
// Why not exceptions: planners and the daemon must turn every failure into a status code and a
// message naming the offending field, and a Result makes that impossible to forget at call sites.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <variant>

namespace skyroute {

enum class ErrorCode {
  kInvalidArgument,   // a parameter is out of range, NaN, or malformed
  kFileNotFound,      // the path does not exist or cannot be read
  kNotARaster,        // GDAL cannot open it as a raster
  kNoCrs,             // the raster has no coordinate reference system
  kBandAmbiguous,     // several bands and none chosen
  kAllNodata,         // every cell is nodata
  kAbsurdHeights,     // heights outside any plausible range on Earth
  kParseError,        // a text file (map, scenario, config, feed) is malformed
  kOutsideMap,        // a point lies outside the terrain or grid
  kOccupied,          // a point lies inside terrain or an obstacle
  kUnreachable,       // no path exists
  kTimeout,           // the deadline passed before a result
  kCancelled,         // the caller cancelled
  kInternal,          // a bug or a library failure; the message says which
};

std::string_view to_string(ErrorCode code);

struct Error {
  ErrorCode code = ErrorCode::kInternal;
  std::string field;    // the input that caused it: a file path, a parameter or point name
  std::string message;  // human readable, names the field and the reason

  std::string describe() const;  // "field: message" (or just message when field is empty)
};

inline Error make_error(ErrorCode code, std::string field, std::string message) {
  return Error{code, std::move(field), std::move(message)};
}

// Holds either a T or an error (an Error unless the layer has a richer one, such as the
// service's PlanError). Access the value only after checking ok().
template <class T, class E = Error>
class Result {
 public:
  Result(T value) : data_(std::move(value)) {}          // NOLINT(google-explicit-constructor)
  Result(E error) : data_(std::move(error)) {}          // NOLINT(google-explicit-constructor)

  bool ok() const { return std::holds_alternative<T>(data_); }
  explicit operator bool() const { return ok(); }

  T& value() & { return std::get<T>(data_); }
  const T& value() const& { return std::get<T>(data_); }
  T&& value() && { return std::get<T>(std::move(data_)); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

  const E& error() const { return std::get<E>(data_); }

 private:
  std::variant<T, E> data_;
};

// Result of an operation with no value.
class Status {
 public:
  Status() = default;
  Status(Error error) : error_(std::move(error)), ok_(false) {}  // NOLINT(google-explicit-constructor)
  static Status success() { return Status(); }
  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  const Error& error() const { return error_; }

 private:
  Error error_;
  bool ok_ = true;
};

}  // namespace skyroute
