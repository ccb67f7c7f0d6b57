#include "planning/core/result.hpp"

#include "planning/core/field_problem.hpp"

namespace skyroute {

std::string_view to_string(ErrorCode code) {
  switch (code) {
    case ErrorCode::kInvalidArgument: return "invalid_argument";
    case ErrorCode::kFileNotFound: return "file_not_found";
    case ErrorCode::kNotARaster: return "not_a_raster";
    case ErrorCode::kNoCrs: return "no_crs";
    case ErrorCode::kBandAmbiguous: return "band_ambiguous";
    case ErrorCode::kAllNodata: return "all_nodata";
    case ErrorCode::kAbsurdHeights: return "absurd_heights";
    case ErrorCode::kParseError: return "parse_error";
    case ErrorCode::kOutsideMap: return "outside_map";
    case ErrorCode::kOccupied: return "occupied";
    case ErrorCode::kUnreachable: return "unreachable";
    case ErrorCode::kTimeout: return "timeout";
    case ErrorCode::kCancelled: return "cancelled";
    case ErrorCode::kInternal: return "internal";
  }
  return "unknown";
}

std::string describeFieldProblem(const std::string& field, const std::string& message) {
  if (field.empty()) return message;
  return field + ": " + message;
}

std::string Error::describe() const { return describeFieldProblem(field, message); }

}  // namespace skyroute
