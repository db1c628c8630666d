// The machine's cores shared among the running jobs as the queue changes (docs/service.md,
// "Cores"): a lone job gets every core, and as more jobs wait or run each gets a smaller share,
// the jobs already running included: their thread budgets shrink, and grow back, up to the
// threads they started with, as the queue drains.
#pragma once

#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

#include "refine/thread_budget.h"

namespace mesh4d::server {

class CoreAllocator {
 public:
  /// `cores` to share, at most `per_job_cap` threads a job, at most `runners` jobs at once.
  CoreAllocator(unsigned cores, unsigned per_job_cap, unsigned runners);

  struct Share {
    unsigned threads;  // the job's workers: its share now, or what it asked within the cap
    std::shared_ptr<refine::ThreadBudget> budget;
  };
  /// A job starting while `queued` others wait; `asked` threads, 0: its share.
  Share start(unsigned asked, std::size_t queued);
  /// A job ended; the others' budgets grow.
  void finish(const Share& share, std::size_t queued);
  /// The queue's length changed: the running jobs' budgets follow.
  void queue_changed(std::size_t queued);

 private:
  struct Running {
    unsigned threads;
    std::shared_ptr<refine::ThreadBudget> budget;
  };
  // The cores of each running job, in order, then of each waiting job that a free runner will
  // start, when `queued` wait; with mu_ held.
  std::vector<unsigned> shares(std::size_t queued) const;
  void rebalance(std::size_t queued);  // with mu_ held

  const unsigned cores_, per_job_cap_, runners_;
  std::mutex mu_;
  std::vector<Running> running_;
};

}  // namespace mesh4d::server
