#include "bench/support/bench_progress.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>

namespace skyroute::bench {
namespace {

double nowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string minutesText(double s) {
  char text[32];
  if (s < 120.0) {
    std::snprintf(text, sizeof text, "%.0f s", s);
  } else {
    std::snprintf(text, sizeof text, "%.1f min", s / 60.0);
  }
  return text;
}

}  // namespace

BenchProgress::BenchProgress(std::string name, std::size_t total)
    : name_(std::move(name)), total_(total), started_s_(nowS()) {
  const char* forced = std::getenv("SKYROUTE_BENCH_PROGRESS");
  enabled_ = (forced != nullptr && std::strcmp(forced, "1") == 0) || isatty(STDERR_FILENO) == 1;
}

void BenchProgress::done(const std::string& what) {
  ++done_;
  if (!enabled_) return;
  const double elapsed_s = nowS() - started_s_;
  std::string line = "[" + std::to_string(done_) + (total_ > 0 ? "/" + std::to_string(total_) : "") + "] " + name_ +
                     ": " + what + " done, " + minutesText(elapsed_s);
  if (total_ > done_) {
    line += ", about " + minutesText(elapsed_s / static_cast<double>(done_) * static_cast<double>(total_ - done_)) + " left";
  }
  std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
}

}  // namespace skyroute::bench
