#include "service/cli/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace skyroute::cli {

TerminalProgress::TerminalProgress(bool forced)
    : enabled_(forced || isatty(STDERR_FILENO) == 1), started_(std::chrono::steady_clock::now()) {}

void TerminalProgress::step(const std::string& what) const {
  if (!enabled_) return;
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  std::fprintf(stderr, "[%6.1f s] %s\n", elapsed_s, what.c_str());
  std::fflush(stderr);
}

}  // namespace skyroute::cli
