#include "core_allocator.h"

#include <algorithm>

namespace mesh4d::server {

CoreAllocator::CoreAllocator(unsigned cores, unsigned per_job_cap, unsigned runners)
    : cores_(std::max(cores, 1u)),
      per_job_cap_(std::max(per_job_cap, 1u)),
      runners_(std::max(runners, 1u)) {}

std::vector<unsigned> CoreAllocator::shares(std::size_t queued) const {
  // The jobs that share the cores soon: those running and the waiting ones that a free runner
  // will start, each of these able to use the cap.
  std::vector<unsigned> caps;
  for (const Running& r : running_) caps.push_back(r.threads);
  const std::size_t free_runners = runners_ > running_.size() ? runners_ - running_.size() : 0;
  caps.insert(caps.end(), std::min(queued, free_runners), per_job_cap_);
  // Water-filling: the cores split evenly, and a job that cannot use its part (it started with
  // fewer threads) leaves the rest to the others; at least one core each.
  std::vector<std::size_t> order(caps.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return caps[a] < caps[b]; });
  std::vector<unsigned> out(caps.size(), 1);
  unsigned remaining = cores_;
  std::size_t left = caps.size();
  for (std::size_t i : order) {
    const unsigned even = std::max(1u, remaining / static_cast<unsigned>(left));
    out[i] = std::min(caps[i], even);
    remaining -= std::min(out[i], remaining);
    --left;
  }
  return out;
}

CoreAllocator::Share CoreAllocator::start(unsigned asked, std::size_t queued) {
  std::lock_guard lock(mu_);
  const unsigned cap = asked ? std::min(asked, per_job_cap_) : per_job_cap_;
  running_.push_back({cap, nullptr});
  // Asked-for threads are kept (and budgeted); otherwise the job starts with its share now.
  const unsigned threads = asked ? cap : shares(queued)[running_.size() - 1];
  running_.back() = {threads, std::make_shared<refine::ThreadBudget>(threads)};
  rebalance(queued);
  return {threads, running_.back().budget};
}

void CoreAllocator::finish(const Share& share, std::size_t queued) {
  std::lock_guard lock(mu_);
  std::erase_if(running_, [&](const Running& r) { return r.budget == share.budget; });
  rebalance(queued);
}

void CoreAllocator::queue_changed(std::size_t queued) {
  std::lock_guard lock(mu_);
  rebalance(queued);
}

void CoreAllocator::rebalance(std::size_t queued) {
  const std::vector<unsigned> limits = shares(queued);
  for (std::size_t i = 0; i < running_.size(); ++i) running_[i].budget->set_limit(limits[i]);
}

}  // namespace mesh4d::server
