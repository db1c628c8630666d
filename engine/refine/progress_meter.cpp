#include "refine/progress_meter.h"

#include <algorithm>

namespace mesh4d::refine {
namespace {

constexpr auto kReportInterval = std::chrono::milliseconds(200);

}  // namespace

double ProgressMeter::elapsed_seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressMeter::report(ProgressSink* sink, Phase phase, bool force) {
  const auto now = std::chrono::steady_clock::now();
  if (!sink || (!force && now - last_report_ < kReportInterval)) return;
  last_report_ = now;
  Progress p = totals();
  p.phase = phase;
  p.vertices = tri_.number_of_vertices();
  // Includes the few infinite ones (cheap); in a parallel phase, the workers' counts added.
  std::int64_t cells = static_cast<std::int64_t>(tri_.number_of_cells());
  if (workers_[0].guard) cells += workers_.live_cells();
  p.pentatopes = static_cast<std::uint64_t>(std::max<std::int64_t>(cells, 0));
  p.elapsed_seconds = std::chrono::duration<double>(now - start_).count();
  sink->on_progress(p);
}

}  // namespace mesh4d::refine
