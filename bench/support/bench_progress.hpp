// Progress of a long benchmark: after each unit of work (a pair, a mission, a seed), one line on
// stderr with how far it is, the time so far and an estimate of the time left. Only on a terminal,
// or with SKYROUTE_BENCH_PROGRESS=1, so the printed tables and CSV files stay as they were.
#pragma once

#include <cstddef>
#include <string>

namespace skyroute::bench {

class BenchProgress {
 public:
  // name: the benchmark; total: how many units it will run (0 when unknown: no estimate).
  BenchProgress(std::string name, std::size_t total);
  // One more unit done; `what` says which ("N44W072 pair 11").
  void done(const std::string& what);

 private:
  std::string name_;
  std::size_t total_ = 0;
  std::size_t done_ = 0;
  bool enabled_ = false;
  double started_s_ = 0.0;
};

}  // namespace skyroute::bench
