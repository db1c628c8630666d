// The rules applied on one thread (docs/algorithm.md, "Refinement"): the bad pentatopes popped
// by rule priority (RuleOrder), one operation each, until no queue holds one.
#pragma once

#include "refine/operation.h"
#include "refine/progress_meter.h"

namespace mesh4d::refine {

/// Drains worker w's queues. Throws Cancelled when the sink asks to stop.
void drain_sequential(RefinementState& state, Operation& operation, Worker& w, ProgressMeter& meter,
                      ProgressSink* sink);

}  // namespace mesh4d::refine
