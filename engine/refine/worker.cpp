#include "refine/worker.h"

namespace mesh4d::refine {

Workers::Workers(delaunay::Triangulation& tri, std::uint64_t seed) : tri_(tri), seed_(seed) {
  workers_.push_back(std::make_unique<Worker>(tri_, 0, seed_));
  workers_[0]->ws = &tri_.workspace();
}

void Workers::ensure(unsigned n) {
  while (workers_.size() < n) {
    const unsigned index = static_cast<unsigned>(workers_.size());
    workers_.push_back(
        std::make_unique<Worker>(tri_, index, seed_ ^ (0x9E3779B97F4A7C15ull * index)));
  }
}

Progress Workers::totals(Progress sum) const {
  for (const auto& w : workers_) {
    for (int r = 0; r < 5; ++r) {
      sum.insertions[r] += w->insertions[r].load(std::memory_order_relaxed);
      sum.removals[r] += w->removals[r].load(std::memory_order_relaxed);
    }
    sum.rollbacks += w->rollbacks.load(std::memory_order_relaxed);
    sum.work_seconds += 1e-9 * double(w->work_ns.load(std::memory_order_relaxed));
    sum.rolled_back_seconds += 1e-9 * double(w->rolled_back_ns.load(std::memory_order_relaxed));
    sum.contention_seconds += 1e-9 * double(w->rolled_back_ns.load(std::memory_order_relaxed) +
                                            w->waiting_ns.load(std::memory_order_relaxed));
    sum.idle_seconds += 1e-9 * double(w->idle_ns.load(std::memory_order_relaxed));
  }
  return sum;
}

std::int64_t Workers::live_cells() const {
  std::int64_t cells = 0;
  for (const auto& w : workers_) cells += w->live_cells.load(std::memory_order_relaxed);
  return cells;
}

}  // namespace mesh4d::refine
