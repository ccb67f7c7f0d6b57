// Request ids per vehicle, so one (vehicle, request id) names one plan: the ids queued or being
// planned, and the final status of the last `capacity` finished ones. A duplicate of a request in
// flight is refused; a duplicate of a finished one is answered with its stored final status, not
// a new plan. Memory is bounded: the oldest finished entries are forgotten first. Not
// thread-safe: the engine calls it under its lock.
#pragma once

#include <cstddef>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "service/mission_types.hpp"

namespace skyroute {

class RequestRegistry {
 public:
  explicit RequestRegistry(std::size_t capacity = 1024) : capacity_(capacity) {}

  bool inFlight(const std::string& vehicle_id, const std::string& request_id) const;
  // The stored final status of a finished request.
  std::optional<PlanStatusData> finished(const std::string& vehicle_id, const std::string& request_id) const;

  void begin(const std::string& vehicle_id, const std::string& request_id);
  // The request's final status (succeeded, failed or cancelled; a later one replaces it, e.g. a
  // mission cancelled after it succeeded). Ends its time in flight.
  void finish(const PlanStatusData& status);
  // Forgets a request in flight without a result (refused before it was queued).
  void abandon(const std::string& vehicle_id, const std::string& request_id);

  void setCapacity(std::size_t capacity);
  std::size_t inFlightCount() const { return in_flight_.size(); }
  std::size_t finishedCount() const { return results_.size(); }

 private:
  using Key = std::pair<std::string, std::string>;  // vehicle id, request id
  void trim();

  std::size_t capacity_;
  std::set<Key> in_flight_;
  std::map<Key, PlanStatusData> results_;
  std::deque<Key> finish_order_;  // each stored key once, oldest first
};

}  // namespace skyroute
