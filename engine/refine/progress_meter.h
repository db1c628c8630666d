// The refinement's progress for a ProgressSink: the workers' counters summed, the triangulation's
// size, and the time since the run started, sent at most every 200 ms unless forced.
#pragma once

#include <chrono>

#include "delaunay/triangulation.h"
#include "refine/progress.h"
#include "refine/worker.h"

namespace mesh4d::refine {

class ProgressMeter {
 public:
  ProgressMeter(const delaunay::Triangulation& tri, const Workers& workers)
      : tri_(tri), workers_(workers) {}

  /// The run's clock starts now.
  void start() { start_ = last_report_ = std::chrono::steady_clock::now(); }
  double elapsed_seconds() const;
  /// Sends the current counts to `sink` (none: nothing), unless the last report is younger
  /// than the interval and `force` is false. Called on the thread that owns the sink.
  void report(ProgressSink* sink, Phase phase, bool force);
  /// Every worker's counters summed.
  Progress totals() const { return workers_.totals(Progress{}); }

 private:
  const delaunay::Triangulation& tri_;
  const Workers& workers_;
  std::chrono::steady_clock::time_point start_, last_report_;
};

}  // namespace mesh4d::refine
