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
    Candidate k;
    if (!pop_live(*queue, state, &k)) continue;  // only dead ones: the next queue
    if (++operations % 256 == 0) {
      if (sink && sink->should_abort()) throw Cancelled();
      meter.report(sink, Phase::refining, false);
    }
    operation.process(w, k);
  }
}

}  // namespace mesh4d::refine
