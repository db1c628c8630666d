// The rules applied by worker threads on one shared triangulation (docs/algorithm.md, "Parallel
// refinement"; the paper's §7.2): vertex locks, rollback on conflict, a contention manager and
// work stealing. The workers, their shared state and the contention manager live in the .cpp.
#pragma once

#include <memory>
#include <vector>

#include "refine/operation.h"
#include "refine/progress_meter.h"

namespace mesh4d::refine {

class ParallelRefiner {
 public:
  /// Runs on RefineParams::threads workers (created in `workers` as needed).
  ParallelRefiner(RefinementState& state, Operation& operation, Workers& workers,
                  ProgressMeter& meter);
  ~ParallelRefiner();
  ParallelRefiner(const ParallelRefiner&) = delete;
  ParallelRefiner& operator=(const ParallelRefiner&) = delete;

  /// Applies the rules until none applies anywhere; worker 0 runs on the calling thread and
  /// alone talks to the sink. Throws Cancelled when the sink asks to stop, and what a worker
  /// threw.
  void drain(ProgressSink* sink);
  /// Inserts the points not within `min_spacing` of a feature vertex, on the job's threads when
  /// there are enough of them (serially otherwise); returns how many went in.
  std::size_t insert_points(const std::vector<RepairPoint>& points, double min_spacing);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mesh4d::refine
