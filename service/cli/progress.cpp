#include "service/cli/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace skyroute::cli {

TerminalProgress::TerminalProgress(bool forced)
    : enabled_(forced || isatty(STDERR_FILENO) == 1),
      started_(std::chrono::steady_clock::now()),
      last_line_(started_) {}

void TerminalProgress::step(const std::string& what) const {
  if (!enabled_) return;
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  std::fprintf(stderr, "[%6.1f s] %s\n", elapsed_s, what.c_str());
  std::fflush(stderr);
  last_line_ = std::chrono::steady_clock::now();
}

void TerminalProgress::every(double period_s, const std::function<std::string()>& what) const {
  if (!enabled_) return;
  if (std::chrono::duration<double>(std::chrono::steady_clock::now() - last_line_).count() < period_s) return;
  step(what());
}

}  // namespace skyroute::cli
