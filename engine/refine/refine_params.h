// Parameters of Delaunay refinement (docs/algorithm.md, "Refinement"), with their defaults and
// checks.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>

#include "refine/thread_budget.h"

namespace mesh4d::refine {

enum class RuleOrder {
  r3_first,  // R3, R1, R2, R4, R5: bounded radius-edge ratio at all times (paper §7.1)
  paper,     // R1, R2, R3, R4, R5
};

struct RefineParams {
  double delta = 5;              // Δ: surface sampling distance, physical units
  double radius_edge_bound = 2;  // ρ̄: pentatopes with circumradius/shortest edge ≥ ρ̄ are refined
  double picking_ratio = 0.5;      // ζ: picking-region radius over circumradius
  unsigned picking_trials = 10;    // random points tried per picking region
  double sliver_bound = 0.01;      // normalized volume below which a pentatope is a sliver
  double max_interior_radius = 0;  // sizing bound on circumradius inside Ω; 0: none
  RuleOrder rule_order = RuleOrder::r3_first;
  std::uint64_t seed = 1;  // of the random picking: same seed and 1 thread, same mesh
  std::uint64_t vertex_budget = 5'000'000;  // refinement stops with an error past this
  // Where three labels meet, sample their junction first, points this far apart relative to Δ
  // (RefinementState::insert_junctions). Off by default: on the patients it did not reduce the
  // pinches (most are on the cavity-myocardium interface, away from junctions;
  // docs/performance.md, "Tried and dropped").
  double junction_spacing = 0;
  // Offset the boundary vertices for the facets' sag (facet_sag.h), so that regions keep their
  // volume; off: every boundary vertex lies on ∂Ω, as in the paper.
  bool sag_offset = true;
  // After the offset, fit each label's section at each frame to its voxels
  // (frame_volume_fit.h). Off only to measure what it does (tests, refine_bench).
  bool fit_frame_volumes = true;
  // Worker threads sharing the triangulation (parallel_refiner.cpp); 1: the sequential path.
  unsigned threads = 1;
  // How many of them may work at once, changed while the job runs; null: all of them.
  std::shared_ptr<const ThreadBudget> thread_budget;
  // Periodic time (domain/periodic_time.h): the oracle's image is the cycle tiled three times,
  // the middle copy from period_start to period_start + period. 0: time is open.
  double period_start = 0;
  double period = 0;
  // How far the covering reaches past each end of the period (domain::tile_cycle's margin
  // frames × the time scale); 0: a whole period, the cycle tiled three times.
  double period_margin = 0;
  // How far past each end of the period the rules' points go in (PeriodicCovering::trusted):
  // twice the interior sizing bound, within the margin; 0: half the margin.
  double period_trusted = 0;
};

/// Bad parameters: the message names the parameter and the accepted range.
class ParamError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Throws ParamError for a non-finite or out-of-range value.
void validate(const RefineParams& params);

/// The threads that may work now: RefineParams::threads within the budget's limit.
inline unsigned working_threads(const RefineParams& params) {
  return params.thread_budget ? std::min(params.threads, params.thread_budget->limit())
                              : params.threads;
}

}  // namespace mesh4d::refine
