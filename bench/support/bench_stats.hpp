// Small statistics the benches print: the bench thread's processor time, nearest-rank quantiles
// and a sample of values with its mean, spread, p95 and maximum.
#pragma once

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace skyroute::bench {

// Processor time of the calling thread, in milliseconds (CLOCK_THREAD_CPUTIME_ID).
inline double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

// Processor time of the whole process (every thread), in milliseconds (CLOCK_PROCESS_CPUTIME_ID).
inline double processCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

// Nearest rank: p99 of 150 samples is the 149th, not an interpolation below the worst ones.
// NaN for no values.
inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::clamp<std::size_t>(rank, 1, v.size()) - 1];
}

struct Sample {
  std::vector<double> v;
  void add(double x) { v.push_back(x); }
  double mean() const {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / static_cast<double>(v.size());
  }
  double stddev() const {
    if (v.size() < 2) return 0.0;
    const double m = mean();
    double s = 0;
    for (double x : v) s += (x - m) * (x - m);
    return std::sqrt(s / static_cast<double>(v.size() - 1));
  }
  double max() const { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }
  // The value at 95 % of the sorted sample (0 for none).
  double p95() const {
    if (v.empty()) return 0.0;
    std::vector<double> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    return sorted[static_cast<std::size_t>(0.95 * static_cast<double>(sorted.size() - 1))];
  }
};

}  // namespace skyroute::bench
