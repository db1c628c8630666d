// What one thread of refinement owns (docs/algorithm.md, "Parallel refinement"): its workspace
// and vertex locks, the picking regions' random numbers and scratch, its queues of bad
// pentatopes (one stack per rule) and its counters. Sequential refinement uses worker 0 without
// locks, on the triangulation's own workspace; in a parallel phase each thread has one.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <random>
#include <utility>
#include <vector>

#include "delaunay/triangulation.h"
#include "delaunay/vertex_locks.h"
#include "refine/progress.h"
#include "refine/rules.h"
#include "support/block_stack.h"

namespace mesh4d::refine {

// The id a trial point's cavity is computed with in a parallel phase, where the next id is not
// known: the newest of all, as the point would be in a sequential run.
inline constexpr mesh4d::VertexId kProvisionalId = delaunay::kNoVertex - 1;

struct Worker {
  Worker(delaunay::Triangulation& tri, unsigned id, std::uint64_t seed)
      : index(id), locks(tri.store(), id + 1), rng(seed) {}

  // After changing queues[r]: under queue_mutex in a parallel phase.
  void publish_length(int r) {
    queued[r].store(static_cast<std::int64_t>(queues[r].size()), std::memory_order_relaxed);
  }

  unsigned index;
  delaunay::CellAllocator cells;  // its pentatope slots in a parallel phase
  delaunay::Triangulation::Workspace own_ws{&cells};
  delaunay::Triangulation::Workspace* ws = nullptr;  // own_ws, or the triangulation's
  delaunay::VertexLocks locks;
  delaunay::CellGuard* guard = nullptr;  // &locks in a parallel phase
  bool conflict = false;                 // the current operation met another thread's lock
  std::mt19937_64 rng;                   // of the picking regions
  delaunay::Cavity trial;                // trial cavities of the picking regions
  std::vector<delaunay::CellId> fresh, created, star;
  std::vector<mesh4d::VertexId> near;               // the free vertices an R5 operation removes
  std::vector<mesh4d::VertexId> removed;            // those of near it did remove
  std::vector<std::pair<int, Candidate>> admitted;  // new pentatopes and their queues, to push
  // In periodic time: each copy's cavity and R5's free vertices near it, claimed before the
  // first write; the pentatopes those change; whether this operation runs alone.
  std::array<delaunay::Cavity, 3> copy_cavity;
  std::array<std::vector<mesh4d::VertexId>, 3> copy_near;
  std::vector<delaunay::CellId> region;
  bool exclusive = false;
  std::mutex queue_mutex;  // the queues, which thieves also take from
  std::array<support::BlockStack<Candidate>, kQueuedRules> queues;  // by index_of(rule)
  // Counters, read by the reporting thread while this one writes them.
  std::array<std::atomic<std::uint64_t>, 5> insertions{}, removals{};
  // Thread time: operations that committed (or had nothing to do), operations rolled back,
  // waits for a lock's holder or the contention manager, and time without work.
  std::atomic<std::uint64_t> rollbacks{0}, work_ns{0}, rolled_back_ns{0}, waiting_ns{0}, idle_ns{0};
  std::atomic<std::int64_t> live_cells{0};  // cells.live, published after each operation
  // Its queues' lengths, for the other workers' R5 gate, on a cache line of its own: counters
  // shared by all workers made every pop and push write one line that every core then fetched.
  alignas(64) std::array<std::atomic<std::int64_t>, kQueuedRules> queued{};
};

// Pops `queue` down to its newest live candidate, into *k; false when only dead ones were left
// (most candidates die in later operations: 72 % on the ventricle at δ = 3). The next
// candidate's pentatope was queued long ago: its loads start before this one is looked at.
inline bool pop_live(support::BlockStack<Candidate>& queue, const RefinementState& state,
                     Candidate* k) {
  while (!queue.empty()) {
    *k = queue.back();
    queue.pop_back();
    if (!queue.empty()) {
      __builtin_prefetch(&state.tri.store().cell(queue.back().cell));
      __builtin_prefetch(&state.info[queue.back().cell]);
    }
    if (state.still_valid(*k)) return true;
  }
  return false;
}

// The workers of a refinement: worker 0 from the start, more for parallel phases.
class Workers {
 public:
  Workers(delaunay::Triangulation& tri, std::uint64_t seed);
  Worker& operator[](unsigned i) { return *workers_[i]; }
  const Worker& operator[](unsigned i) const { return *workers_[i]; }
  unsigned size() const { return static_cast<unsigned>(workers_.size()); }
  /// At least n workers; worker i's random numbers are seeded from the seed and i.
  void ensure(unsigned n);
  /// `base` plus every worker's counters.
  Progress totals(Progress base) const;
  /// The pentatopes that the workers of a parallel phase hold beyond the triangulation's count.
  std::int64_t live_cells() const;

 private:
  delaunay::Triangulation& tri_;
  std::uint64_t seed_;
  std::vector<std::unique_ptr<Worker>> workers_;
};

}  // namespace mesh4d::refine
