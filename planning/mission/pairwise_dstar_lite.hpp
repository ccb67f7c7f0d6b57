// The baseline the seed compares MMD*L with: one independent D* Lite (its own g/rhs map and
// queue) for every planned start/goal pair, n^2+n maps for n mission points.
#pragma once

#include <map>
#include <memory>
#include <utility>

#include "planning/grid/dstar_lite.hpp"
#include "planning/mission/mission_search.hpp"

namespace skyroute {

class PairwiseDStarLite final : public MissionSearch {
 public:
  PairwiseDStarLite(const GridLayer& grid, std::vector<GridCell> points, const GridMoves& moves = {});

  std::string_view name() const override { return "dstar-lite"; }
  SearchStatus preplan(const TerminationCondition& stop = {}) override;
  SearchStatus applyChanges(std::span<const GridCell> changed, const TerminationCondition& stop = {}) override;
  double cost(int from_point, int to_point) const override;
  std::vector<GridCell> path(int from_point, int to_point) const override;
  GridCell nextCell(int goal_point) const override;
  std::size_t costMapCount() const override { return pairs_.size(); }
  void moveVehicle(GridCell cell) override;
  void arriveAt(int point) override;

  // The map of a planned pair (nullptr otherwise); for diagnostics and tests.
  const DStarGoalField* field(int from_point, int to_point) const {
    const auto it = pairs_.find({from_point, to_point});
    return it == pairs_.end() ? nullptr : &it->second->field();
  }

 private:
  SearchStatus run(DStarLite& search, const TerminationCondition& stop);

  std::shared_ptr<GridMoveTable> table_;  // shared by every pair (it holds no search state)
  std::map<std::pair<int, int>, std::unique_ptr<DStarLite>> pairs_;  // (start, goal)
};

}  // namespace skyroute
