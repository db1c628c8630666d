// Parallel refinement: the rules applied by worker threads on one shared triangulation
// (docs/algorithm.md, "Parallel refinement"; the paper's Section 7.2).
//
// Each worker pops a bad pentatope from its own queues and runs the same operation as the
// sequential refiner (Operation::process), but under vertex locks: the pentatope's vertices
// first, then every pentatope that a walk, a cavity, a picking-region trial or an R5 removal
// reads (delaunay/cell_guard.h). All locks are taken before the first write; a lock held by
// another thread rolls the operation back (nothing was written). The worker then waits, holding
// no lock, until that thread lets go of the vertex, and tries the same pentatope again: its
// next candidates lie around the same place and would meet the same thread. (Setting the
// pentatope aside and going on rolled back three times as often on 16 cores, and the token
// below, taken often then, stopped every worker.) No thread waits while it holds a lock, so
// the waits cannot close a cycle. New pentatopes go to the worker's own queues.
//
// Progress: a worker that rolled back kPriorityAfter times in a row takes the contention
// manager's token; the others finish (or roll back) their current operation and wait until it
// commits one, so some thread always commits: no livelock, even with more threads than cores.
// Rule priority across workers: R5 work waits while another worker runs an R1–R4 operation
// (and is traded for others' queued R1–R4 work), as R5 comes last in the sequential order.
// Balance: a worker without work steals the older half of another's queues; the phase ends
// when every worker is idle at once (a count that a thief leaves before it looks, so that a
// stolen candidate is never in flight while the count is full).
#include "refine/parallel_refiner.h"

#include <algorithm>
#include <exception>
#include <thread>

#include "support/parallel_parts.h"

namespace mesh4d::refine {

using delaunay::CellId;
using delaunay::VertexKind;
using mesh4d::VertexId;

namespace {

constexpr unsigned kPriorityAfter = 64;        // consecutive rollbacks before taking the token
constexpr std::uint64_t kPollEvery = 64;       // operations between worker 0's abort checks
constexpr unsigned kYieldsBeforeSleep = 4096;  // waiting for a lock's holder
constexpr std::size_t kRepairShare = 8;        // repair points per thread, at least

using Clock = std::chrono::steady_clock;

std::uint64_t nanoseconds_between(Clock::time_point t0, Clock::time_point t1) {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
}
std::uint64_t nanoseconds_since(Clock::time_point t0) {
  return nanoseconds_between(t0, Clock::now());
}

// Puts a popped candidate back on its worker's queue (thieves take from it meanwhile).
void requeue(Worker& w, Rule rule, const Candidate& k) {
  std::lock_guard lock(w.queue_mutex);
  w.queues[index_of(rule)].push_back(k);
  w.publish_length(index_of(rule));
}

// Spin politely: yield first, then sleep, so that oversubscribed threads let the others run.
void back_off(unsigned& spins) {
  if (++spins < 16)
    std::this_thread::yield();
  else
    std::this_thread::sleep_for(std::chrono::microseconds(50));
}

}  // namespace

struct ParallelRefiner::Impl {
  Impl(RefinementState& state, Operation& operation, Workers& workers, ProgressMeter& meter)
      : state_(state),
        operation_(operation),
        workers_(workers),
        meter_(meter),
        order_(priority_order(state.params.rule_order)) {}

  struct Shared;
  struct Lane;
  void drain(ProgressSink* sink);
  std::size_t insert_points(const std::vector<RepairPoint>& points, double min_spacing);
  // A parallel phase's frame: storage and workers ready, each worker on its own workspace and
  // locks; then, after the threads joined, their pentatopes merged back for serial work.
  void enter_parallel(unsigned threads);
  void leave_parallel(unsigned threads);
  // One thread of a parallel phase.
  void work(Worker& w, Shared& shared, ProgressSink* sink);
  bool pop(Worker& w, Shared& shared, Candidate* k, Rule* rule);
  // Takes the older half of another worker's queues (of one rule only, unless Rule::none).
  bool steal(Worker& w, Shared& shared, Rule only = Rule::none);
  bool queued_anywhere(const Shared& shared, Rule rule) const;  // in any worker's queues
  static bool queued_here(const Worker& w);                     // in w's queues, any rule
  bool higher_in_flight(const Shared& shared) const;  // an R1–R4 operation under way anywhere
  void distribute_work(unsigned threads);             // all queued work split among the workers
  // Past the job's thread budget: waits, counted idle and holding no work, until the budget
  // takes it back or the phase ends.
  void pause(Worker& w, Shared& shared);
  // With the token held: waits until no other worker is inside an operation (so that none holds
  // a lock); false when the phase stops meanwhile.
  bool wait_alone(Worker& w, Shared& shared);

  RefinementState& state_;
  Operation& operation_;
  Workers& workers_;
  ProgressMeter& meter_;
  const std::array<Rule, kQueuedRules> order_;
  std::vector<std::unique_ptr<Lane>> lanes_;  // by worker index
};

struct ParallelRefiner::Impl::Shared {
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

// The parallel refiner's own part of a worker: what only the flow between threads needs.
struct ParallelRefiner::Impl::Lane {
  std::uint64_t operations = 0;
  unsigned consecutive_rollbacks = 0;
  // Whether it runs an operation of a rule other than R5 (the others' R5 gate), on a cache line
  // of its own.
  alignas(64) std::atomic<bool> higher_in_flight{false};
  // Whether it is inside an operation: a worker that must run alone (Outcome::exclusive) holds
  // the token and waits until no other is.
  alignas(64) std::atomic<bool> busy{false};
};

ParallelRefiner::ParallelRefiner(RefinementState& state, Operation& operation, Workers& workers,
                                 ProgressMeter& meter)
    : impl_(std::make_unique<Impl>(state, operation, workers, meter)) {}
ParallelRefiner::~ParallelRefiner() = default;
void ParallelRefiner::drain(ProgressSink* sink) {
  impl_->drain(sink);
}
std::size_t ParallelRefiner::insert_points(const std::vector<RepairPoint>& points,
                                           double min_spacing) {
  return impl_->insert_points(points, min_spacing);
}

bool ParallelRefiner::Impl::pop(Worker& w, Shared& shared, Candidate* k, Rule* rule) {
  for (int attempt = 0; attempt < 2; ++attempt) {
    std::unique_lock lock(w.queue_mutex);
    while (true) {
      Rule own = Rule::none;
      for (Rule r : order_)
        if (!w.queues[index_of(r)].empty()) {
          own = r;
          break;
        }
      // The rules' priority is global in the sequential refiner: R5 runs only once no other
      // rule applies anywhere. Its free-vertex removals next to another worker's R3 insertions
      // undo them and are undone in turn, so a worker left with R5 work takes others' work
      // first.
      if (own == Rule::R5 && attempt == 0) {
        Rule higher = Rule::none;
        for (Rule r : order_) {
          if (r == Rule::R5) break;
          if (queued_anywhere(shared, r)) {
            higher = r;
            break;
          }
        }
        if (higher != Rule::none) {
          lock.unlock();
          steal(w, shared, higher);
          break;  // the next attempt
        }
      }
      if (own == Rule::none) return false;
      // Dead candidates (often killed in another worker's region) are dropped here, under the
      // one lock, before process() locks their vertices.
      const bool live = pop_live(w.queues[index_of(own)], state_, k);
      w.publish_length(index_of(own));
      if (live) {
        *rule = own;
        return true;
      }  // only dead ones: the next queue
    }
  }
  return false;
}

bool ParallelRefiner::Impl::steal(Worker& w, Shared& shared, Rule only) {
  // The older half of each queue: far from where the victim works now, so fewer conflicts.
  for (unsigned i = 1; i < shared.threads; ++i) {
    Worker& victim = workers_[(w.index + i) % shared.threads];
    std::array<std::vector<Candidate>, kQueuedRules> taken;
    std::size_t total = 0;
    {
      std::lock_guard lock(victim.queue_mutex);
      for (int r = 0; r < kQueuedRules; ++r) {
        if (only != Rule::none && r != index_of(only)) continue;
        auto& q = victim.queues[r];
        q.take_bottom((q.size() + 1) / 2, taken[r]);
        const std::size_t m = taken[r].size();
        victim.publish_length(r);
        total += m;
      }
    }
    if (total == 0) continue;
    std::lock_guard lock(w.queue_mutex);
    for (int r = 0; r < kQueuedRules; ++r) {
      w.queues[r].append(taken[r].begin(), taken[r].end());
      w.publish_length(r);
    }
    return true;
  }
  return false;
}

bool ParallelRefiner::Impl::queued_anywhere(const Shared& shared, Rule rule) const {
  for (unsigned t = 0; t < shared.threads; ++t)
    if (workers_[t].queued[index_of(rule)].load(std::memory_order_relaxed) > 0) return true;
  return false;
}

bool ParallelRefiner::Impl::queued_here(const Worker& w) {
  for (int r = 0; r < kQueuedRules; ++r)
    if (w.queued[r].load(std::memory_order_relaxed) > 0) return true;
  return false;
}

bool ParallelRefiner::Impl::higher_in_flight(const Shared& shared) const {
  for (unsigned t = 0; t < shared.threads; ++t)
    if (lanes_[t]->higher_in_flight.load(std::memory_order_acquire)) return true;
  return false;
}

void ParallelRefiner::Impl::distribute_work(unsigned threads) {
  // Everything queued goes into one pool per rule, then each worker gets a
  // contiguous share: neighbors in the queue are mostly neighbors in space.
  std::array<std::vector<Candidate>, kQueuedRules> pool;
  for (unsigned t = 0; t < workers_.size(); ++t) {
    Worker& w = workers_[t];
    for (int r = 0; r < kQueuedRules; ++r) {
      w.queues[r].copy_to(pool[r]);
      w.queues[r].clear();
    }
  }
  for (int r = 0; r < kQueuedRules; ++r) {
    const std::size_t n = pool[r].size();
    for (unsigned t = 0; t < threads; ++t) {
      const auto begin = pool[r].begin() + static_cast<std::ptrdiff_t>(n * t / threads);
      const auto end = pool[r].begin() + static_cast<std::ptrdiff_t>(n * (t + 1) / threads);
      workers_[t].queues[r].assign(begin, end);
      workers_[t].publish_length(r);
    }
  }
}

void ParallelRefiner::Impl::pause(Worker& w, Shared& shared) {
  // Its queued work goes to worker 0, which never pauses: an idle worker holds no work, or the
  // phase could end with some left.
  Worker& keeper = workers_[0];
  {
    std::scoped_lock lock(w.queue_mutex, keeper.queue_mutex);
    for (int r = 0; r < kQueuedRules; ++r) {
      std::vector<Candidate> moved;
      w.queues[r].copy_to(moved);
      w.queues[r].clear();
      keeper.queues[r].append(moved.begin(), moved.end());
    }
    for (int r = 0; r < kQueuedRules; ++r) w.publish_length(r), keeper.publish_length(r);
  }
  const auto t0 = Clock::now();
  if (shared.idle.fetch_add(1, std::memory_order_acq_rel) + 1 == shared.threads)
    shared.finished.store(true, std::memory_order_release);
  while (shared.running() && w.index >= working_threads(state_.params))
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  shared.idle.fetch_sub(1, std::memory_order_acq_rel);
  w.idle_ns.fetch_add(nanoseconds_since(t0), std::memory_order_relaxed);
}

bool ParallelRefiner::Impl::wait_alone(Worker& w, Shared& shared) {
  const auto t0 = Clock::now();
  unsigned spins = 0;
  bool alone = false;
  while (!alone && shared.running()) {
    alone = true;
    for (unsigned t = 0; t < shared.threads && alone; ++t)
      alone = t == w.index || !lanes_[t]->busy.load(std::memory_order_seq_cst);
    if (!alone) back_off(spins);
  }
  w.waiting_ns.fetch_add(nanoseconds_since(t0), std::memory_order_relaxed);
  return alone;
}

void ParallelRefiner::Impl::work(Worker& w, Shared& shared, ProgressSink* sink) {
  Lane& lane = *lanes_[w.index];
  const int me = static_cast<int>(w.index);
  // Worker 0 runs on the caller's thread: it alone talks to the sink.
  const auto tick = [&] {
    if (!sink) return;
    if (sink->should_abort()) {
      shared.fail(std::make_exception_ptr(Cancelled()));
      return;
    }
    meter_.report(sink, Phase::refining, false);
  };
  const auto release_priority = [&] {
    // Others only take a free token: a plain store once the load saw it ours. (A
    // compare-exchange after every operation wrote the line that every worker reads each step.)
    if (shared.priority.load(std::memory_order_relaxed) == me)
      shared.priority.store(-1, std::memory_order_release);
  };
  // One clock reading per operation: each operation's time runs from the end of the last one
  // (or of a wait), so that the queue work before it counts as its own.
  Clock::time_point last = Clock::now();
  try {
    while (shared.running()) {
      if (w.index >= working_threads(state_.params)) {
        release_priority();
        pause(w, shared);
        last = Clock::now();
        continue;
      }
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
        last = Clock::now();
        w.waiting_ns.fetch_add(nanoseconds_between(t0, last), std::memory_order_relaxed);
        continue;
      }

      Candidate k;
      Rule rule;
      if (!pop(w, shared, &k, &rule)) {
        if (steal(w, shared)) continue;
        release_priority();  // nothing to run alone
        const auto t0 = Clock::now();
        unsigned spins = 0;
        bool counted = false;
        while (shared.running()) {
          if (counted) shared.idle.fetch_sub(1, std::memory_order_acq_rel), counted = false;
          // Its own queues too: a pausing worker hands its work to worker 0 (pause()).
          if (queued_here(w) || steal(w, shared)) break;
          counted = true;
          if (shared.idle.fetch_add(1, std::memory_order_acq_rel) + 1 == shared.threads) {
            shared.finished.store(true, std::memory_order_release);
            break;
          }
          if (w.index == 0) tick();
          back_off(spins);
        }
        last = Clock::now();
        w.idle_ns.fetch_add(nanoseconds_between(t0, last), std::memory_order_relaxed);
        continue;
      }

      if (state_.tri.stamps_running_low()) {  // cleared between phases, by one thread
        requeue(w, rule, k);
        shared.stop.store(true, std::memory_order_release);
        break;
      }
      // R5 removes free vertices near its point: beside another worker's R3 insertion it undoes
      // work that is then redone (more pentatopes, more rollbacks). It waits, queued, instead.
      if (rule == Rule::R5 && higher_in_flight(shared)) {
        requeue(w, rule, k);
        const auto t0 = Clock::now();
        unsigned spins = 0;
        while (shared.running() && higher_in_flight(shared)) {
          if (w.index == 0) tick();
          back_off(spins);
        }
        last = Clock::now();
        w.waiting_ns.fetch_add(nanoseconds_between(t0, last), std::memory_order_relaxed);
        continue;
      }
      // Inside an operation from here: a worker waiting to run alone sees this, or this sees
      // its token (both sequentially consistent, so one of the two must).
      lane.busy.store(true, std::memory_order_seq_cst);
      if (const int h = shared.priority.load(std::memory_order_seq_cst); h >= 0 && h != me) {
        lane.busy.store(false, std::memory_order_release);
        requeue(w, rule, k);
        continue;
      }
      if (rule != Rule::R5) lane.higher_in_flight.store(true, std::memory_order_release);
      if (w.index == 0 && ++lane.operations % kPollEvery == 0) tick();
      Outcome outcome = operation_.process(w, k);
      if (outcome == Outcome::exclusive) {
        // In periodic time, a point's copies whose regions touch (the cells are still large):
        // run it alone, once no other worker is inside an operation. Nothing was written.
        w.locks.release_all();
        lane.busy.store(false, std::memory_order_release);
        if (rule != Rule::R5) lane.higher_in_flight.store(false, std::memory_order_release);
        int none = -1;
        shared.priority.compare_exchange_strong(none, me, std::memory_order_seq_cst);
        if (shared.priority.load(std::memory_order_seq_cst) != me) {
          requeue(w, rule, k);  // another runs alone first
          continue;
        }
        lane.busy.store(true, std::memory_order_seq_cst);
        if (!wait_alone(w, shared)) {
          lane.busy.store(false, std::memory_order_release);
          requeue(w, rule, k);
          break;
        }
        last = Clock::now();  // (the wait was counted)
        if (rule != Rule::R5) lane.higher_in_flight.store(true, std::memory_order_release);
        w.exclusive = true;
        outcome = operation_.process(w, k);
        w.exclusive = false;
      }
      if (rule != Rule::R5) lane.higher_in_flight.store(false, std::memory_order_release);
      const auto blocker = w.locks.take_blocker();
      w.locks.release_all();
      lane.busy.store(false, std::memory_order_release);
      w.live_cells.store(w.cells.live, std::memory_order_relaxed);
      const auto ended = Clock::now();
      const std::uint64_t operation_ns = nanoseconds_between(last, ended);
      last = ended;
      if (outcome == Outcome::conflict) {
        w.rollbacks.fetch_add(1, std::memory_order_relaxed);
        w.rolled_back_ns.fetch_add(operation_ns, std::memory_order_relaxed);
        // Wait for the holder to let go: it commits or rolls back within one operation (tens of
        // microseconds), so yield, and sleep only when it takes far longer (a thread the system
        // parked). A feature sampled nearby meanwhile names no thread: tried again at once.
        if (blocker) {
          for (unsigned spins = 0; w.locks.still_held(*blocker) && shared.running(); ++spins) {
            if (spins < kYieldsBeforeSleep)
              std::this_thread::yield();
            else
              std::this_thread::sleep_for(std::chrono::microseconds(50));
          }
        }
        last = Clock::now();
        w.waiting_ns.fetch_add(nanoseconds_between(ended, last), std::memory_order_relaxed);
        requeue(w, rule, k);
        if (++lane.consecutive_rollbacks >= kPriorityAfter) {
          int none = -1;
          shared.priority.compare_exchange_strong(none, me, std::memory_order_acq_rel);
        }
      } else {
        w.work_ns.fetch_add(operation_ns, std::memory_order_relaxed);
        lane.consecutive_rollbacks = 0;
        release_priority();
      }
    }
  } catch (...) {
    w.locks.release_all();
    shared.fail(std::current_exception());
  }
  release_priority();
}

void ParallelRefiner::Impl::enter_parallel(unsigned threads) {
  state_.prepare_concurrent();
  workers_.ensure(threads);
  while (lanes_.size() < threads) lanes_.push_back(std::make_unique<Lane>());
  for (unsigned t = 0; t < threads; ++t) {
    Worker& w = workers_[t];
    Lane& lane = *lanes_[t];
    w.ws = &w.own_ws;
    w.guard = &w.locks;
    lane.consecutive_rollbacks = 0;
    lane.higher_in_flight.store(false, std::memory_order_relaxed);  // (a phase that failed)
    lane.busy.store(false, std::memory_order_relaxed);
  }
}

void ParallelRefiner::Impl::leave_parallel(unsigned threads) {
  for (unsigned t = 0; t < threads; ++t) {
    Worker& w = workers_[t];
    w.locks.release_all();
    state_.tri.merge(w.own_ws);
    w.live_cells.store(0, std::memory_order_relaxed);
    w.guard = nullptr;
    w.ws = nullptr;
  }
  workers_[0].ws = &state_.tri.workspace();
}

void ParallelRefiner::Impl::drain(ProgressSink* sink) {
  const unsigned threads = state_.params.threads;
  while (true) {
    enter_parallel(threads);
    if (state_.tri.stamps_running_low()) state_.tri.clear_stamps();
    distribute_work(threads);
    Shared shared(threads);
    {
      std::vector<std::jthread> pool;
      for (unsigned t = 1; t < threads; ++t)
        pool.emplace_back([this, &shared, t] { work(workers_[t], shared, nullptr); });
      work(workers_[0], shared, sink);
    }  // joined
    leave_parallel(threads);
    if (shared.error) std::rethrow_exception(shared.error);
    // Every worker idle, yet work may be queued: a worker that paused handed its queues to
    // worker 0 after worker 0 had counted itself idle, and its own count ended the phase.
    // Another phase takes that work.
    bool left = false;
    for (int r = 0; r < kQueuedRules && !left; ++r)
      left = queued_anywhere(shared, static_cast<Rule>(r));
    if (shared.finished.load() && !left) return;
    // Stopped because the visit stamps ran low (cleared when the next phase starts), or work
    // was left: go on with what is queued.
  }
}

std::size_t ParallelRefiner::Impl::insert_points(const std::vector<RepairPoint>& points,
                                                 double min_spacing) {
  std::size_t inserted = 0;
  const auto insert_serially = [&](const RepairPoint& r) {
    // A point already sampled nearby would make a short edge and change little.
    if (state_.feature_within(r.point, min_spacing)) return;
    // (A dead hint is ignored.)
    inserted += operation_.insert(workers_[0], r.point, VertexKind::feature, r.hint.cell,
                                  Rule::R1) == Outcome::done;
  };
  // A share of a few points is not worth a thread (the first rounds have hundreds).
  const unsigned threads = static_cast<unsigned>(
      std::min<std::size_t>(working_threads(state_.params), points.size() / kRepairShare));
  if (threads <= 1 || state_.tri.stamps_running_low()) {
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
    support::run_parts(threads, [&](unsigned part) {
      Worker& w = workers_[part];
      const auto [begin, end] = support::part_range(points.size(), part, threads);
      for (std::size_t i = begin; i < end; ++i) {
        const RepairPoint& r = points[i];
        if (state_.feature_within(r.point, min_spacing)) continue;
        bool held = true;
        for (VertexId u : r.hint.v) held = held && w.locks.lock(u);
        Outcome outcome = Outcome::conflict;
        // The ball is checked again under the feature index's lock (another thread's point).
        if (held && state_.still_valid(r.hint))
          outcome = operation_.insert(w, r.point, VertexKind::feature, r.hint.cell, Rule::R1,
                                      &r.point, min_spacing);
        w.locks.release_all();
        if (outcome == Outcome::done) ++done[part];
        if (outcome == Outcome::conflict || outcome == Outcome::exclusive) later[part].push_back(i);
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
