#include "planning/mission/mission_search.hpp"

namespace skyroute {

MissionSearch::MissionSearch(const GridLayer& grid, std::vector<GridCell> points, const GridMoves& moves)
    : grid_(&grid), points_(std::move(points)), moves_(moves), visited_(points_.size(), 0) {
  vehicle_cell_ = points_.empty() ? GridCell{} : points_.front();
  last_cell_ = vehicle_cell_;
  if (!visited_.empty()) visited_[0] = 1;
}

void MissionSearch::moveVehicle(GridCell cell) { vehicle_cell_ = cell; }

void MissionSearch::arriveAt(int point) {
  vehicle_point_ = point;
  vehicle_cell_ = points_[static_cast<std::size_t>(point)];
  last_cell_ = vehicle_cell_;
  visited_[static_cast<std::size_t>(point)] = 1;
  km_ = 0.0;  // line 77: the new vehicle start's queue was keyed with k_m = 0
}

void MissionSearch::accumulateKm() {
  km_ += moves_.estimate(last_cell_, vehicle_cell_);
  last_cell_ = vehicle_cell_;
}

std::vector<int> MissionSearch::remainingMissions() const {
  std::vector<int> out;
  for (int p = 1; p <= missionCount(); ++p)
    if (!visited(p)) out.push_back(p);
  return out;
}

std::vector<int> MissionSearch::remainingGoals() const {
  std::vector<int> out = remainingMissions();
  out.push_back(endPoint());
  return out;
}

std::vector<int> MissionSearch::startsFor(int goal_point) const {
  std::vector<int> out;
  if (planned(vehicle_point_, goal_point)) out.push_back(vehicle_point_);
  for (int p : remainingMissions())
    if (p != goal_point) out.push_back(p);
  return out;
}

bool MissionSearch::planned(int from, int to) const {
  if (from < 0 || to < 0 || from >= pointCount() || to >= pointCount() || from == to) return false;
  if (to == 0 || visited(to) || from == endPoint()) return false;
  if (from != vehicle_point_ && visited(from)) return false;
  if (from == vehicle_point_ && to == endPoint() && !remainingMissions().empty()) return false;
  return true;
}

}  // namespace skyroute
