#include "refine/sequential_refiner.h"

namespace mesh4d::refine {

void drain_sequential(RefinementState& state, Operation& operation, Worker& w, ProgressMeter& meter,
                      ProgressSink* sink) {
  // Priority: the order of the rules (R3 first by default), through one stack per rule.
  const auto order = priority_order(state.params.rule_order);
  std::uint64_t operations = 0;
  while (true) {
    support::BlockStack<Candidate>* queue = nullptr;
    for (Rule r : order)
      if (!w.queues[index_of(r)].empty()) {
        queue = &w.queues[index_of(r)];
        break;
      }
    if (!queue) return;
    const Candidate k = queue->back();
    queue->pop_back();
    // The next candidate's pentatope was queued long ago: its loads start now.
    if (!queue->empty()) {
      __builtin_prefetch(&state.tri.store().cell(queue->back().cell));
      __builtin_prefetch(&state.info[queue->back().cell]);
    }
    if (!state.still_valid(k)) continue;
    if (++operations % 256 == 0) {
      if (sink && sink->should_abort()) throw Cancelled();
      meter.report(sink, Phase::refining, false);
    }
    operation.process(w, k);
  }
}

}  // namespace mesh4d::refine
