// When a planner must stop: a deadline, an iteration budget, or a cancel request, whichever first.
// Planners take one of these instead of loose flags (as OMPL's PlannerTerminationCondition), so the
// daemon can cancel an in-flight plan from another thread.
// A deadline is either wall-clock (steady clock) or in the calling thread's CPU time: the latter
// makes benchmarks on a shared, loaded machine compare planners on the work they did rather than
// on how often the scheduler let them run.
#pragma once

#include <time.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string_view>

namespace skyroute {

class TerminationCondition {
 public:
  using Clock = std::chrono::steady_clock;
  enum class Reason { kNone, kDeadline, kIterations, kCancelled };

  TerminationCondition() = default;

  static TerminationCondition after(std::chrono::nanoseconds budget) {
    TerminationCondition t;
    t.deadline_ = Clock::now() + budget;
    return t;
  }
  static TerminationCondition afterMilliseconds(double budget_ms) {
    return after(std::chrono::nanoseconds(static_cast<std::int64_t>(budget_ms * 1e6)));
  }
  // Deadline in CPU time of the calling thread: only meaningful when shouldStop() is asked from
  // the thread that built the condition (each thread has its own CPU clock).
  static TerminationCondition afterThreadCpu(std::chrono::nanoseconds budget) {
    TerminationCondition t;
    t.cpu_deadline_ = threadCpuNow() + budget;
    return t;
  }
  static TerminationCondition afterThreadCpuMilliseconds(double budget_ms) {
    return afterThreadCpu(std::chrono::nanoseconds(static_cast<std::int64_t>(budget_ms * 1e6)));
  }
  // CPU time consumed so far by the calling thread.
  static std::chrono::nanoseconds threadCpuNow() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
  }
  // Also stops `budget` from now: the earlier of that and a wall-clock deadline already set.
  TerminationCondition& withDeadlineAfter(std::chrono::nanoseconds budget) {
    const Clock::time_point at = Clock::now() + budget;
    if (!deadline_ || at < *deadline_) deadline_ = at;
    return *this;
  }
  TerminationCondition& withIterationBudget(std::uint64_t iterations) {
    max_iterations_ = iterations;
    return *this;
  }
  // The flag is shared: setting it from any thread stops the planner at its next check.
  TerminationCondition& withCancelFlag(std::shared_ptr<std::atomic<bool>> cancel) {
    cancel_ = std::move(cancel);
    return *this;
  }

  // iterations_done: the planner's own count, compared with the iteration budget.
  bool shouldStop(std::uint64_t iterations_done = 0) const { return reason(iterations_done) != Reason::kNone; }
  Reason reason(std::uint64_t iterations_done = 0) const {
    if (cancel_ && cancel_->load(std::memory_order_relaxed)) return Reason::kCancelled;
    if (iterations_done >= max_iterations_) return Reason::kIterations;
    if (deadline_ && Clock::now() >= *deadline_) return Reason::kDeadline;
    if (cpu_deadline_ && threadCpuNow() >= *cpu_deadline_) return Reason::kDeadline;
    return Reason::kNone;
  }
  bool hasDeadline() const { return deadline_.has_value() || cpu_deadline_.has_value(); }
  // The shared cancel flag (nullptr when none), for work outside the planners that must stop too.
  const std::atomic<bool>* cancelFlag() const { return cancel_.get(); }
  // The same flag shared, for a later stage that keeps it (a replanner that outlives this plan).
  const std::shared_ptr<std::atomic<bool>>& sharedCancelFlag() const { return cancel_; }

 private:
  std::optional<Clock::time_point> deadline_;
  std::optional<std::chrono::nanoseconds> cpu_deadline_;  // thread CPU time
  std::uint64_t max_iterations_ = std::numeric_limits<std::uint64_t>::max();
  std::shared_ptr<std::atomic<bool>> cancel_;
};

inline std::string_view to_string(TerminationCondition::Reason r) {
  switch (r) {
    case TerminationCondition::Reason::kNone: return "none";
    case TerminationCondition::Reason::kDeadline: return "deadline";
    case TerminationCondition::Reason::kIterations: return "iterations";
    case TerminationCondition::Reason::kCancelled: return "cancelled";
  }
  return "unknown";
}

}  // namespace skyroute
