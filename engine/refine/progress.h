// How the refiner reports progress and is told to stop, without knowing who listens (the
// service, a CLI, a test): a small interface, called from the refining thread.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>

namespace mesh4d::refine {

enum class Phase { loading, distance_map, refining, extracting, writing };

struct Progress {
  Phase phase = Phase::refining;
  std::uint64_t vertices = 0;
  std::uint64_t pentatopes = 0;               // finite pentatopes of the triangulation
  std::array<std::uint64_t, 5> insertions{};  // per rule R1..R5
  std::array<std::uint64_t, 5> removals{};
  std::uint64_t rollbacks = 0;  // operations undone on a lock conflict (parallel phases)
  // Thread time of the parallel phases, summed over the workers: in operations that committed
  // or found nothing to do (each with the queue work before it); lost to conflicts
  // (rolled_back_seconds of it in the operations undone, the rest waiting for a lock's holder or
  // the contention manager); without work.
  double work_seconds = 0;
  double contention_seconds = 0;
  double rolled_back_seconds = 0;
  double idle_seconds = 0;
  double elapsed_seconds = 0;
};

class ProgressSink {
 public:
  virtual ~ProgressSink() = default;
  /// Called at most every `interval` (the refiner's setting) and once per phase change.
  virtual void on_progress(const Progress& progress) = 0;
  /// Polled often (every few hundred operations); true stops refinement with Cancelled.
  virtual bool should_abort() { return false; }
};

/// Thrown when a ProgressSink asked to stop.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("refinement cancelled") {}
};

/// Thrown when refinement needs more vertices than RefineParams::vertex_budget allows.
class BudgetExceeded : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace mesh4d::refine
