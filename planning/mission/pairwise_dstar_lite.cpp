#include "planning/mission/pairwise_dstar_lite.hpp"

namespace skyroute {

PairwiseDStarLite::PairwiseDStarLite(const GridLayer& grid, std::vector<GridCell> points, const GridMoves& moves)
    : MissionSearch(grid, std::move(points), moves) {}

SearchStatus PairwiseDStarLite::run(DStarLite& search, const TerminationCondition& stop) {
  const SearchStats before = search.stats();
  const SearchStatus s = search.computeShortestPath(stop);
  const SearchStats& after = search.stats();
  stats_.expansions += after.expansions - before.expansions;
  stats_.queue_pushes += after.queue_pushes - before.queue_pushes;
  stats_.queue_pops += after.queue_pops - before.queue_pops;
  stats_.time_ms += after.time_ms - before.time_ms;
  return s;
}

SearchStatus PairwiseDStarLite::preplan(const TerminationCondition& stop) {
  pairs_.clear();
  table_ = std::make_shared<GridMoveTable>(*grid_, moves_);
  for (int goal : remainingGoals()) {
    for (int start : startsFor(goal)) {
      auto search = std::make_unique<DStarLite>(table_, startCell(start), points_[goal]);
      // The initial goal insertion is a queue operation of this pair too.
      stats_.queue_pushes += search->stats().queue_pushes;
      search->resetStats();
      if (run(*search, stop) == SearchStatus::kStopped) return SearchStatus::kStopped;
      pairs_.emplace(std::make_pair(start, goal), std::move(search));
    }
  }
  return SearchStatus::kFound;
}

SearchStatus PairwiseDStarLite::applyChanges(std::span<const GridCell> changed, const TerminationCondition& stop) {
  if (changed.empty()) return SearchStatus::kFound;
  accumulateKm();
  // The vehicle's pairs add h(last, now) to their k_m inside updateCells.
  for (auto& [key, search] : pairs_) search->updateCells(changed);
  for (auto& [key, search] : pairs_)
    if (run(*search, stop) == SearchStatus::kStopped) return SearchStatus::kStopped;
  return SearchStatus::kFound;
}

double PairwiseDStarLite::cost(int from, int to) const {
  if (!planned(from, to)) return kInfiniteCost;
  const auto it = pairs_.find({from, to});
  return it == pairs_.end() ? kInfiniteCost : it->second->cost();
}

std::vector<GridCell> PairwiseDStarLite::path(int from, int to) const {
  if (!planned(from, to)) return {};
  const auto it = pairs_.find({from, to});
  return it == pairs_.end() ? std::vector<GridCell>{} : it->second->path();
}

GridCell PairwiseDStarLite::nextCell(int goal) const {
  const auto it = pairs_.find({vehicle_point_, goal});
  return it == pairs_.end() ? vehicle_cell_ : it->second->nextCell();
}

void PairwiseDStarLite::moveVehicle(GridCell cell) {
  MissionSearch::moveVehicle(cell);
  for (auto& [key, search] : pairs_)
    if (key.first == vehicle_point_) search->moveStart(cell);
}

void PairwiseDStarLite::arriveAt(int point) {
  const int old_vehicle = vehicle_point_;
  MissionSearch::arriveAt(point);
  std::erase_if(pairs_, [&](const auto& kv) {
    const auto& [from, to] = kv.first;
    return from == old_vehicle || to == point || !planned(from, to);
  });
}

}  // namespace skyroute
