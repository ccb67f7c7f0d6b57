#include "service/request_registry.hpp"

namespace skyroute {

bool RequestRegistry::inFlight(const std::string& vehicle_id, const std::string& request_id) const {
  return in_flight_.count({vehicle_id, request_id}) > 0;
}

std::optional<PlanStatusData> RequestRegistry::finished(const std::string& vehicle_id,
                                                        const std::string& request_id) const {
  if (auto it = results_.find({vehicle_id, request_id}); it != results_.end()) return it->second;
  return std::nullopt;
}

void RequestRegistry::begin(const std::string& vehicle_id, const std::string& request_id) {
  in_flight_.insert({vehicle_id, request_id});
}

void RequestRegistry::abandon(const std::string& vehicle_id, const std::string& request_id) {
  in_flight_.erase({vehicle_id, request_id});
}

void RequestRegistry::finish(const PlanStatusData& status) {
  Key key{status.vehicle_id, status.request_id};
  in_flight_.erase(key);
  if (capacity_ == 0) return;
  const bool known = results_.count(key) > 0;
  results_[key] = status;
  if (!known) finish_order_.push_back(std::move(key));
  trim();
}

void RequestRegistry::setCapacity(std::size_t capacity) {
  capacity_ = capacity;
  trim();
}

void RequestRegistry::trim() {
  while (results_.size() > capacity_ && !finish_order_.empty()) {
    results_.erase(finish_order_.front());
    finish_order_.pop_front();
  }
}

}  // namespace skyroute
