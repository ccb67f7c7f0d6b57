#include "planning/fleet/fleet_ga.hpp"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <random>

namespace skyroute {
namespace {

struct Genome {
  std::vector<int> vehicle;  // per task
  std::vector<double> key;   // per task, visiting order within a vehicle
  long long fitness = 0;     // makespan * 2^32 + sum of route steps (lower is better)
};

constexpr long long kInfeasible = std::numeric_limits<long long>::max();

class GeneticAllocator {
 public:
  GeneticAllocator(const FleetProblem& problem, const TravelTimeTable& table, const FleetGaOptions& options)
      : problem_(problem), table_(table), options_(options), rng_(options.seed) {}

  std::vector<std::vector<int>> decode(const Genome& g) const {
    std::vector<std::vector<int>> seq(static_cast<std::size_t>(problem_.vehicleCount()));
    std::vector<int> order(g.vehicle.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return g.key[a] != g.key[b] ? g.key[a] < g.key[b] : a < b; });
    for (int j : order) seq[g.vehicle[j]].push_back(j);
    return seq;
  }

  void evaluate(Genome& g) {
    ++evaluations_;
    long long makespan = 0;
    long long sum = 0;
    const auto seq = decode(g);
    for (std::size_t i = 0; i < seq.size(); ++i) {
      const int t = routeSteps(table_, static_cast<int>(i), seq[i]);
      if (t == kUnreachableSteps || static_cast<int>(seq[i].size()) > problem_.capacity(static_cast<int>(i))) {
        g.fitness = kInfeasible;
        return;
      }
      makespan = std::max<long long>(makespan, t);
      sum += t;
    }
    g.fitness = (makespan << 32) + sum;
  }

  // Moves tasks off vehicles that cannot reach them or are over capacity, to the vehicle with the
  // most room left that reaches them (lowest index on ties).
  void repair(Genome& g) const {
    const int nu = problem_.vehicleCount();
    std::vector<int> load(static_cast<std::size_t>(nu), 0);
    std::vector<int> order(g.vehicle.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return g.key[a] != g.key[b] ? g.key[a] < g.key[b] : a < b; });
    for (int j : order) {
      int& v = g.vehicle[j];
      if (table_.depotToTask(v, j) != kUnreachableSteps && load[v] < problem_.capacity(v)) {
        ++load[v];
        continue;
      }
      int best = -1;
      for (int i = 0; i < nu; ++i) {
        if (table_.depotToTask(i, j) == kUnreachableSteps || load[i] >= problem_.capacity(i)) continue;
        if (best < 0 || problem_.capacity(i) - load[i] > problem_.capacity(best) - load[best]) best = i;
      }
      if (best >= 0) v = best;
      ++load[v];
    }
  }

  Genome randomGenome() {
    Genome g;
    const int nt = problem_.taskCount();
    std::uniform_int_distribution<int> pick(0, problem_.vehicleCount() - 1);
    for (int j = 0; j < nt; ++j) {
      g.vehicle.push_back(pick(rng_));
      g.key.push_back(unit_(rng_));
    }
    repair(g);
    evaluate(g);
    return g;
  }

  const Genome& tournament(const std::vector<Genome>& pop) {
    std::uniform_int_distribution<std::size_t> pick(0, pop.size() - 1);
    const Genome* best = &pop[pick(rng_)];
    for (int k = 1; k < options_.tournament; ++k) {
      const Genome& c = pop[pick(rng_)];
      if (c.fitness < best->fitness) best = &c;
    }
    return *best;
  }

  void mutate(Genome& g) {
    const int nt = problem_.taskCount();
    std::uniform_int_distribution<int> task(0, nt - 1);
    std::uniform_int_distribution<int> vehicle(0, problem_.vehicleCount() - 1);
    if (unit_(rng_) < options_.mutation_rate) {  // move one task to another vehicle and place
      const int j = task(rng_);
      g.vehicle[j] = vehicle(rng_);
      g.key[j] = unit_(rng_);
    }
    if (unit_(rng_) < options_.mutation_rate) {  // exchange two tasks (vehicle and place)
      const int a = task(rng_);
      const int b = task(rng_);
      std::swap(g.vehicle[a], g.vehicle[b]);
      std::swap(g.key[a], g.key[b]);
    }
    if (unit_(rng_) < options_.mutation_rate) {  // reverse a stretch of one vehicle's order
      const int v = g.vehicle[task(rng_)];
      std::vector<int> mine;
      for (int j = 0; j < nt; ++j) {
        if (g.vehicle[j] == v) mine.push_back(j);
      }
      std::sort(mine.begin(), mine.end(), [&](int a, int b) { return g.key[a] != g.key[b] ? g.key[a] < g.key[b] : a < b; });
      if (mine.size() >= 2) {
        std::uniform_int_distribution<std::size_t> at(0, mine.size() - 1);
        std::size_t lo = at(rng_);
        std::size_t hi = at(rng_);
        if (lo > hi) std::swap(lo, hi);
        std::vector<double> keys;
        for (std::size_t k = lo; k <= hi; ++k) keys.push_back(g.key[mine[k]]);
        for (std::size_t k = lo; k <= hi; ++k) g.key[mine[k]] = keys[hi - k];
      }
    }
  }

  Result<FleetAllocation> run(const TerminationCondition& stop) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<Genome> pop;
    for (int p = 0; p < options_.population; ++p) pop.push_back(randomGenome());
    auto better = [](const Genome& a, const Genome& b) { return a.fitness < b.fitness; };
    for (int gen = 0; gen < options_.generations && !stop.shouldStop(static_cast<std::uint64_t>(gen)); ++gen) {
      std::stable_sort(pop.begin(), pop.end(), better);
      std::vector<Genome> next(pop.begin(), pop.begin() + std::min<std::size_t>(options_.elite, pop.size()));
      while (static_cast<int>(next.size()) < options_.population) {
        Genome child = tournament(pop);
        if (unit_(rng_) < options_.crossover_rate) {
          const Genome& other = tournament(pop);
          for (std::size_t j = 0; j < child.vehicle.size(); ++j) {
            if (unit_(rng_) < 0.5) {
              child.vehicle[j] = other.vehicle[j];
              child.key[j] = other.key[j];
            }
          }
        }
        mutate(child);
        repair(child);
        evaluate(child);
        next.push_back(std::move(child));
      }
      pop = std::move(next);
    }
    const Genome& best = *std::min_element(pop.begin(), pop.end(), better);
    if (best.fitness == kInfeasible) {
      return make_error(ErrorCode::kUnreachable, "tasks",
                        "the genetic algorithm found no allocation in which every vehicle reaches its tasks");
    }
    FleetAllocation out;
    out.algorithm = "ga";
    out.sequences = decode(best);
    refreshAllocationCosts(table_, out);
    out.evaluations = evaluations_;
    out.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  }

 private:
  const FleetProblem& problem_;
  const TravelTimeTable& table_;
  FleetGaOptions options_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> unit_{0.0, 1.0};
  std::uint64_t evaluations_ = 0;
};

}  // namespace

Result<FleetAllocation> allocateGenetic(const FleetProblem& problem, const TravelTimeTable& table,
                                        const FleetGaOptions& options, const TerminationCondition& stop) {
  if (options.population < 2) {
    return make_error(ErrorCode::kInvalidArgument, "population", "population must be at least 2");
  }
  if (options.generations < 0) {
    return make_error(ErrorCode::kInvalidArgument, "generations", "generations must not be negative");
  }
  if (options.tournament < 1) {
    return make_error(ErrorCode::kInvalidArgument, "tournament", "tournament size must be at least 1");
  }
  if (options.elite < 0 || options.elite >= options.population) {
    return make_error(ErrorCode::kInvalidArgument, "elite", "elite must be in [0, population)");
  }
  if (problem.taskCount() == 0) {
    FleetAllocation out;
    out.algorithm = "ga";
    out.sequences.assign(static_cast<std::size_t>(problem.vehicleCount()), {});
    refreshAllocationCosts(table, out);
    return out;
  }
  GeneticAllocator ga(problem, table, options);
  return ga.run(stop);
}

}  // namespace skyroute
