// HAB-PP's pheromone field: evaporation and deposit of eqs. (3) and (4) over the cells the ranked
// paths touch (Fig. 3), and the roulette wheel the RRT* species samples it by.
#include "planning/colony/hab_pp.hpp"

#include <algorithm>
#include <cmath>

#include "planning/colony/hab_pp_detail.hpp"

namespace skyroute::habpp {

PheromoneField::PheromoneField(const GridFields& fields, const HabPpParameters& params)
    : fields_(&fields), params_(params), tau_(fields.grid().cellCount()), stamp_(fields.grid().cellCount(), 0),
      in_active_(fields.grid().cellCount(), 0) {
  const GridLayer& grid = fields.grid();
  for (std::size_t i = 0; i < tau_.size(); ++i) {
    const GridCell c = grid.cellOf(i);
    // Choice: blocked cells start (and stay) at the floor: no ant or sample reads them and no path
    // deposits on them, so the update and the sampling need not look at them.
    tau_[i] = grid.passable(c) ? std::clamp(fields.visibility(c), params.pheromone_min, params.pheromone_max)
                               : params.pheromone_min;
    if (grid.passable(c)) free_cells_.push_back(i);
    if (tau_[i] > params.pheromone_min) {
      in_active_[i] = 1;
      active_.push_back(static_cast<std::uint32_t>(i));
    }
  }
  if (params.rrt_ants > 0 && params.rrt_sample_visibility) {
    eta_beta_.assign(tau_.size(), 0.0);
    floor_eta_cumulative_.reserve(free_cells_.size());
    double sum = 0.0;
    for (std::size_t i : free_cells_) {
      eta_beta_[i] = powExponent(fields.visibility(grid.cellOf(i)), params.beta);
      sum += eta_beta_[i];
      floor_eta_cumulative_.push_back(sum);
    }
  }
}

void PheromoneField::nextStamp() {
  if (++stamp_now_ == 0) {  // wrapped: clear the stamps once
    std::fill(stamp_.begin(), stamp_.end(), 0);
    stamp_now_ = 1;
  }
}

std::vector<std::uint32_t> PheromoneField::pathCells(const Path& path) {
  const GridLayer& grid = fields_->grid();
  std::vector<std::uint32_t> cells;
  nextStamp();
  for (std::size_t s = 0; s + 1 < path.size(); ++s) {
    for (GridCell c : segmentCells(path[s], path[s + 1])) {  // Fig. 3: the cells between points too
      if (!grid.inside(c)) continue;
      const std::size_t i = grid.index(c);
      if (stamp_[i] == stamp_now_) continue;
      stamp_[i] = stamp_now_;
      cells.push_back(static_cast<std::uint32_t>(i));
    }
  }
  return cells;
}

void PheromoneField::update(const std::vector<Path>& ranked, const std::vector<double>& evaluation) {
  std::vector<std::vector<std::uint32_t>> cells;
  cells.reserve(ranked.size());
  for (const Path& p : ranked) cells.push_back(pathCells(p));
  updateCells(cells, evaluation);
}

void PheromoneField::updateCells(const std::vector<std::vector<std::uint32_t>>& ranked_cells,
                                 const std::vector<double>& evaluation) {
  const double keep = 1.0 - params_.rho;
  for (std::uint32_t i : active_) tau_[i] *= keep;
  for (std::size_t k = 0; k < ranked_cells.size(); ++k) {
    const double deposit = params_.rho * evaluation[k];
    for (std::uint32_t i : ranked_cells[k]) {
      if (in_active_[i] == 0) {  // at the floor: evaporate it here, as the full pass would have
        in_active_[i] = 1;
        active_.push_back(i);
        tau_[i] *= keep;
      }
      tau_[i] += deposit;
    }
  }
  std::size_t kept = 0;
  for (std::uint32_t i : active_) {
    tau_[i] = std::clamp(tau_[i], params_.pheromone_min, params_.pheromone_max);
    if (tau_[i] > params_.pheromone_min) {
      active_[kept++] = i;
    } else {
      in_active_[i] = 0;
    }
  }
  active_.resize(kept);
  excess_table_ = ExcessTable::kStale;
}

GridCell PheromoneField::sample(Rng& rng) const { return sampleWeighted(rng, false); }

GridCell PheromoneField::sampleWithVisibility(Rng& rng) const {
  // eta^beta is tabulated only for a colony with RRT* ants and rrt_sample_visibility.
  return sampleWeighted(rng, !floor_eta_cumulative_.empty());
}

GridCell PheromoneField::sampleWeighted(Rng& rng, bool with_eta) const {
  const GridLayer& grid = fields_->grid();
  const double floor_weight = powExponent(params_.pheromone_min, params_.alpha);
  const ExcessTable wanted = with_eta ? ExcessTable::kWithEta : ExcessTable::kPheromoneOnly;
  if (excess_table_ != wanted) {
    excess_cells_.clear();
    excess_cumulative_.clear();
    double sum = 0.0;
    excess_cells_.reserve(active_.size());
    excess_cumulative_.reserve(active_.size());
    for (std::uint32_t i : active_) {  // all free: blocked cells stay at the floor
      sum += (powExponent(tau_[i], params_.alpha) - floor_weight) * (with_eta ? eta_beta_[i] : 1.0);
      excess_cells_.push_back(i);
      excess_cumulative_.push_back(sum);
    }
    excess_table_ = wanted;
  }
  const double excess = excess_cumulative_.empty() ? 0.0 : excess_cumulative_.back();
  const double floor_sum = with_eta ? floor_eta_cumulative_.back() : static_cast<double>(free_cells_.size());
  const double r = std::uniform_real_distribution<double>(0.0, excess + floor_weight * floor_sum)(rng);
  if (r < excess) {
    const auto it = std::upper_bound(excess_cumulative_.begin(), excess_cumulative_.end(), r);
    const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(it - excess_cumulative_.begin()),
                                                excess_cells_.size() - 1);
    return grid.cellOf(excess_cells_[k]);
  }
  const double at = (r - excess) / floor_weight;  // a position in the floor part, in floor cells
  const std::size_t k =
      with_eta ? static_cast<std::size_t>(std::upper_bound(floor_eta_cumulative_.begin(), floor_eta_cumulative_.end(), at) -
                                          floor_eta_cumulative_.begin())
               : static_cast<std::size_t>(at);
  return grid.cellOf(free_cells_[std::min<std::size_t>(k, free_cells_.size() - 1)]);
}

}  // namespace skyroute::habpp
