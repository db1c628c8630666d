// How many of a job's threads may work at once: a server that shares its cores among jobs
// lowers the limit while other jobs wait and raises it again as they end. The refiner starts
// RefineParams::threads workers; those past the limit pause between operations, holding no
// lock and no work (parallel_refiner.cpp), and the stages that split work among threads
// split it among the working ones.
#pragma once

#include <algorithm>
#include <atomic>

namespace mesh4d::refine {

class ThreadBudget {
 public:
  explicit ThreadBudget(unsigned limit) : limit_(std::max(limit, 1u)) {}
  unsigned limit() const { return limit_.load(std::memory_order_relaxed); }
  /// At least 1: the thread that runs the job always works.
  void set_limit(unsigned n) { limit_.store(std::max(n, 1u), std::memory_order_relaxed); }

 private:
  std::atomic<unsigned> limit_;
};

}  // namespace mesh4d::refine
