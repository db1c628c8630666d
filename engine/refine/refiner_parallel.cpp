// Parallel refinement: the rules applied by worker threads on one shared triangulation
// (ALGORITHM.md, "Parallel refinement"; the paper's Section 7.2).
//
// Each worker pops a bad pentatope from its own queues and runs the same operation as the
// sequential refiner (Refiner::process), but under vertex locks: the pentatope's vertices
// first, then every pentatope that a walk, a cavity, a picking-region trial or an R5 removal
// reads (delaunay/cell_guard.h). All locks are taken before the first write; a lock held by
// another thread rolls the operation back (nothing was written) and the pentatope is tried
// again later. New pentatopes go to the worker's own queues.
//
// Progress: a worker that rolled back kPriorityAfter times in a row takes the contention
// manager's token; the others finish (or roll back) their current operation and wait until it
// commits one, so some thread always commits: no livelock, even with more threads than cores.
// Rule priority across workers: R5 work waits while another worker runs an R1–R4 operation
// (and is traded for others' queued R1–R4 work), as R5 comes last in the sequential order.
// Balance: a worker without work steals the older half of another's queues; the phase ends
// when every worker is idle at once (a count that a thief leaves before it looks, so that a
// stolen candidate is never in flight while the count is full).
#include <algorithm>
#include <exception>
#include <thread>

#include "delaunay/parallel_parts.h"
#include "refine/refiner.h"

namespace mesh4d::refine {

using delaunay::CellId;
using delaunay::VertexKind;

namespace {

constexpr unsigned kPriorityAfter = 16;   // consecutive rollbacks before taking the token
constexpr std::uint64_t kPollEvery = 64;  // operations between worker 0's abort checks
constexpr std::size_t kRepairShare = 8;   // repair points per thread, at least

using Clock = std::chrono::steady_clock;

std::uint64_t nanoseconds_since(Clock::time_point t0) {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count());
}

// Spin politely: yield first, then sleep, so that oversubscribed threads let the others run.
void back_off(unsigned& spins) {
  if (++spins < 16)
    std::this_thread::yield();
  else
    std::this_thread::sleep_for(std::chrono::microseconds(50));
}

}  // namespace

struct Refiner::Shared {
  explicit Shared(unsigned n) : threads(n) {}
  const unsigned threads;
  // Read by every worker at every step and written rarely, so each on a line of its own: a
  // write to a line invalidates it in every core that reads it.
  alignas(64) std::atomic<bool> stop{false};  // cancelled, failed, or out of stamps: leave now
  std::atomic<bool> finished{false};          // every worker idle: no work is left anywhere
  alignas(64) std::atomic<int> priority{-1};  // the worker the contention manager lets run alone
  alignas(64) std::atomic<unsigned> idle{0};
  alignas(64) std::mutex error_mutex;
  std::exception_ptr error;

  void fail(std::exception_ptr e) {
    {
      std::lock_guard lock(error_mutex);
      if (!error) error = std::move(e);
    }
    stop.store(true, std::memory_order_release);
  }
  bool running() const {
    return !stop.load(std::memory_order_acquire) && !finished.load(std::memory_order_acquire);
  }
};

bool Refiner::pop(Worker& w, Shared& shared, Candidate* k, Rule* rule) {
  const std::array<Rule, 6> order = params_.rule_order == RuleOrder::r3_first
                                        ? std::array<Rule, 6>{kR3, kR1, kR2, kR4, kSizing, kR5}
                                        : std::array<Rule, 6>{kR1, kR2, kR3, kR4, kSizing, kR5};
  for (int attempt = 0; attempt < 2; ++attempt) {
    std::unique_lock lock(w.queue_mutex);
    Rule own = kNone;
    for (Rule r : order)
      if (!w.queues[r].empty()) {
        own = r;
        break;
      }
    // The rules' priority is global in the sequential refiner: R5 runs only once no other rule
    // applies anywhere. Its free-vertex removals next to another worker's R3 insertions undo
    // them and are undone in turn, so a worker left with R5 work takes others' work first.
    if (own == kR5 && attempt == 0) {
      Rule higher = kNone;
      for (Rule r : order) {
        if (r == kR5) break;
        if (queued_anywhere(shared, r)) {
          higher = r;
          break;
        }
      }
      if (higher != kNone) {
        lock.unlock();
        steal(w, shared, higher);
        continue;
      }
    }
    if (own == kNone) return false;
    *k = w.queues[own].back();
    w.queues[own].pop_back();
    w.publish_length(own);
    *rule = own;
    return true;
  }
  return false;
}

bool Refiner::steal(Worker& w, Shared& shared, Rule only) {
  // The older half of each queue: far from where the victim works now, so fewer conflicts.
  for (unsigned i = 1; i < shared.threads; ++i) {
    Worker& victim = *workers_[(w.index + i) % shared.threads];
    std::array<std::vector<Candidate>, kNone> taken;
    std::size_t total = 0;
    {
      std::lock_guard lock(victim.queue_mutex);
      for (int r = 0; r < kNone; ++r) {
        if (only != kNone && r != only) continue;
        auto& q = victim.queues[r];
        q.take_bottom((q.size() + 1) / 2, taken[r]);
        const std::size_t m = taken[r].size();
        victim.publish_length(r);
        total += m;
      }
    }
    if (total == 0) continue;
    std::lock_guard lock(w.queue_mutex);
    for (int r = 0; r < kNone; ++r) {
      w.queues[r].append(taken[r].begin(), taken[r].end());
      w.publish_length(r);
    }
    return true;
  }
  return false;
}

bool Refiner::queued_anywhere(const Shared& shared, Rule rule) const {
  for (unsigned t = 0; t < shared.threads; ++t)
    if (workers_[t]->queued[rule].load(std::memory_order_relaxed) > 0) return true;
  return false;
}

bool Refiner::higher_in_flight(const Shared& shared) const {
  for (unsigned t = 0; t < shared.threads; ++t)
    if (workers_[t]->higher_in_flight.load(std::memory_order_acquire)) return true;
  return false;
}

void Refiner::distribute_work(unsigned threads) {
  // Everything queued (and rolled back) goes into one pool per rule, then each worker gets a
  // contiguous share: neighbors in the queue are mostly neighbors in space.
  std::array<std::vector<Candidate>, kNone> pool;
  for (auto& w : workers_) {
    for (int r = 0; r < kNone; ++r) {
      w->queues[r].copy_to(pool[r]);
      w->queues[r].clear();
    }
    for (const auto& [k, r] : w->retry) pool[r].push_back(k);
    w->retry.clear();
  }
  for (int r = 0; r < kNone; ++r) {
    const std::size_t n = pool[r].size();
    for (unsigned t = 0; t < threads; ++t) {
      const auto begin = pool[r].begin() + static_cast<std::ptrdiff_t>(n * t / threads);
      const auto end = pool[r].begin() + static_cast<std::ptrdiff_t>(n * (t + 1) / threads);
      workers_[t]->queues[r].assign(begin, end);
      workers_[t]->publish_length(r);
    }
  }
}

void Refiner::work(Worker& w, Shared& shared, ProgressSink* sink) {
  const int me = static_cast<int>(w.index);
  // Worker 0 runs on the caller's thread: it alone talks to the sink.
  const auto tick = [&] {
    if (!sink) return;
    if (sink->should_abort()) {
      shared.fail(std::make_exception_ptr(Cancelled()));
      return;
    }
    report(sink, Phase::refining, false);
  };
  const auto release_priority = [&] {
    // Others only take a free token: a plain store once the load saw it ours. (A
    // compare-exchange after every operation wrote the line that every worker reads each step.)
    if (shared.priority.load(std::memory_order_relaxed) == me)
      shared.priority.store(-1, std::memory_order_release);
  };
  try {
    while (shared.running()) {
      const int holder = shared.priority.load(std::memory_order_acquire);
      if (holder >= 0 && holder != me) {
        // Another worker runs alone until it commits: wait, holding no lock.
        const auto t0 = Clock::now();
        unsigned spins = 0;
        while (shared.running()) {
          const int h = shared.priority.load(std::memory_order_acquire);
          if (h < 0 || h == me) break;
          if (w.index == 0) tick();
          back_off(spins);
        }
        w.contention_ns.fetch_add(nanoseconds_since(t0), std::memory_order_relaxed);
        continue;
      }

      Candidate k;
      Rule rule;
      if (!pop(w, shared, &k, &rule)) {
        // Fresh work first (another's queue), then what rolled back: retrying at once would
        // mostly meet the same locks again.
        if (steal(w, shared)) continue;
        if (!w.retry.empty()) {
          std::lock_guard lock(w.queue_mutex);
          for (const auto& [candidate, r] : w.retry) w.queues[r].push_back(candidate);
          for (int r = 0; r < kNone; ++r) w.publish_length(r);
          w.retry.clear();
          continue;
        }
        release_priority();  // nothing to run alone
        const auto t0 = Clock::now();
        unsigned spins = 0;
        bool counted = false;
        while (shared.running()) {
          if (counted) shared.idle.fetch_sub(1, std::memory_order_acq_rel), counted = false;
          if (steal(w, shared)) break;
          counted = true;
          if (shared.idle.fetch_add(1, std::memory_order_acq_rel) + 1 == shared.threads) {
            shared.finished.store(true, std::memory_order_release);
            break;
          }
          if (w.index == 0) tick();
          back_off(spins);
        }
        w.idle_ns.fetch_add(nanoseconds_since(t0), std::memory_order_relaxed);
        continue;
      }

      // Most candidates died in later operations (72 % on the ventricle at δ = 3), often in
      // another worker's region: a lock-free look at the record drops them before process()
      // locks their vertices (fewer rollbacks with 8 and 16 threads; no change in time seen).
      if (!still_valid(k)) continue;
      if (tri_.stamps_running_low()) {  // cleared between phases, by one thread
        std::lock_guard lock(w.queue_mutex);
        w.queues[rule].push_back(k);
        w.publish_length(rule);
        shared.stop.store(true, std::memory_order_release);
        break;
      }
      // R5 removes free vertices near its point: beside another worker's R3 insertion it undoes
      // work that is then redone (more pentatopes, more rollbacks). It waits, queued, instead.
      if (rule == kR5 && higher_in_flight(shared)) {
        {
          std::lock_guard lock(w.queue_mutex);
          w.queues[rule].push_back(k);
          w.publish_length(rule);
        }
        const auto t0 = Clock::now();
        unsigned spins = 0;
        while (shared.running() && higher_in_flight(shared)) {
          if (w.index == 0) tick();
          back_off(spins);
        }
        w.contention_ns.fetch_add(nanoseconds_since(t0), std::memory_order_relaxed);
        continue;
      }
      if (rule != kR5) w.higher_in_flight.store(true, std::memory_order_release);
      if (w.index == 0 && ++w.operations % kPollEvery == 0) tick();
      const auto t0 = Clock::now();
      const Outcome outcome = process(w, k);
      if (rule != kR5) w.higher_in_flight.store(false, std::memory_order_release);
      w.locks.release_all();
      w.live_cells.store(w.cells.live, std::memory_order_relaxed);
      if (outcome == Outcome::conflict) {
        w.rollbacks.fetch_add(1, std::memory_order_relaxed);
        w.contention_ns.fetch_add(nanoseconds_since(t0), std::memory_order_relaxed);
        w.retry.emplace_back(k, rule);
        if (++w.consecutive_rollbacks >= kPriorityAfter) {
          int none = -1;
          shared.priority.compare_exchange_strong(none, me, std::memory_order_acq_rel);
        } else if (w.consecutive_rollbacks > 2) {
          // Give the holder time to finish before trying near it again.
          unsigned spins = w.consecutive_rollbacks;
          back_off(spins);
        }
      } else {
        w.consecutive_rollbacks = 0;
        release_priority();
      }
    }
  } catch (...) {
    w.locks.release_all();
    shared.fail(std::current_exception());
  }
  release_priority();
}

void Refiner::enter_parallel(unsigned threads) {
  if (!concurrent_ready_) {
    // Vertex ids: the budget, plus the ids of rolled-back insertions and removed vertices.
    tri_.prepare_concurrent(std::max<std::uint64_t>(4 * params_.vertex_budget, 1u << 20));
    info_.reserve_blocks(std::size_t{delaunay::kNoCell} + 1);
    concurrent_ready_ = true;
  }
  while (workers_.size() < threads) {
    const unsigned index = static_cast<unsigned>(workers_.size());
    workers_.push_back(
        std::make_unique<Worker>(tri_, index, params_.seed ^ (0x9E3779B97F4A7C15ull * index)));
  }
  for (unsigned t = 0; t < threads; ++t) {
    Worker& w = *workers_[t];
    w.ws = &w.own_ws;
    w.guard = &w.locks;
    w.consecutive_rollbacks = 0;
    w.higher_in_flight.store(false, std::memory_order_relaxed);  // (a phase that failed)
  }
}

void Refiner::leave_parallel(unsigned threads) {
  for (unsigned t = 0; t < threads; ++t) {
    Worker& w = *workers_[t];
    w.locks.release_all();
    tri_.merge(w.own_ws);
    w.live_cells.store(0, std::memory_order_relaxed);
    w.guard = nullptr;
    w.ws = nullptr;
  }
  workers_[0]->ws = &tri_.workspace();
}

void Refiner::drain_parallel(ProgressSink* sink) {
  const unsigned threads = params_.threads;
  while (true) {
    enter_parallel(threads);
    if (tri_.stamps_running_low()) tri_.clear_stamps();
    distribute_work(threads);
    Shared shared(threads);
    {
      std::vector<std::jthread> pool;
      for (unsigned t = 1; t < threads; ++t)
        pool.emplace_back([this, &shared, t] { work(*workers_[t], shared, nullptr); });
      work(*workers_[0], shared, sink);
    }  // joined
    leave_parallel(threads);
    if (shared.error) std::rethrow_exception(shared.error);
    if (shared.finished.load()) return;
    // Stopped because the visit stamps ran low: clear them and go on with what is queued.
  }
}

std::size_t Refiner::insert_repair_points(const std::vector<RepairPoint>& points,
                                          double min_spacing) {
  std::size_t inserted = 0;
  const auto insert_serially = [&](const RepairPoint& r) {
    // A point already sampled nearby would make a short edge and change little.
    if (feature_within(r.point, min_spacing)) return;
    // (A dead hint is ignored.)
    inserted += insert_and_admit(*workers_[0], r.point, VertexKind::feature, r.hint.cell, kR1) ==
                Outcome::done;
  };
  // A share of a few points is not worth a thread (the first rounds have hundreds).
  const unsigned threads =
      static_cast<unsigned>(std::min<std::size_t>(params_.threads, points.size() / kRepairShare));
  if (threads <= 1 || tri_.stamps_running_low()) {
    for (const RepairPoint& r : points) insert_serially(r);
    return inserted;
  }
  // Each thread a contiguous share (the points come in triangle order), under the rules'
  // locks: the hint pentatope first, as a rule's operation holds its candidate. What meets
  // another thread's locks, or a hint its own insertions killed, goes in afterwards, serially.
  std::vector<std::vector<std::size_t>> later(threads);
  std::vector<std::size_t> done(threads, 0);
  enter_parallel(threads);
  try {
    delaunay::run_parts(threads, [&](unsigned part) {
      Worker& w = *workers_[part];
      const auto [begin, end] = delaunay::part_range(points.size(), part, threads);
      for (std::size_t i = begin; i < end; ++i) {
        const RepairPoint& r = points[i];
        if (feature_within(r.point, min_spacing)) continue;
        bool held = true;
        for (VertexId u : r.hint.v) held = held && w.locks.lock(u);
        Outcome outcome = Outcome::conflict;
        // The ball is checked again under the feature index's lock (another thread's point).
        if (held && still_valid(r.hint))
          outcome = insert_and_admit(w, r.point, VertexKind::feature, r.hint.cell, kR1, &r.point,
                                     min_spacing);
        w.locks.release_all();
        if (outcome == Outcome::done) ++done[part];
        if (outcome == Outcome::conflict) later[part].push_back(i);
      }
    });
  } catch (...) {
    leave_parallel(threads);
    throw;
  }
  leave_parallel(threads);
  for (std::size_t n : done) inserted += n;
  for (const auto& part : later)
    for (std::size_t i : part) insert_serially(points[i]);
  return inserted;
}

}  // namespace mesh4d::refine
