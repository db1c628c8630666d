// Pinch repair (docs/algorithm.md, "Where labels meet"): where three labels meet, the paper's
// rules, proven for one label, can leave a label's region boundary pinched. The restricted
// facets around each pinched triangle are sampled at their surface centers (points of ∂Ω on
// their Voronoi edges, as R5 uses), which splits them, and the rules run again; in rounds, with
// the spacing to earlier samples halved when the count stalls (RepairPolicy), so the work
// stays bounded.
#pragma once

#include <functional>
#include <vector>

#include "refine/facet_log.h"
#include "refine/operation.h"
#include "refine/pinch_counts.h"
#include "refine/pinch_scan.h"

namespace mesh4d::refine {

class PinchRepair {
 public:
  /// Applies the rules until none applies.
  using Drain = std::function<void()>;
  /// Inserts repair points not within the spacing of a feature vertex; returns how many.
  using Insert = std::function<std::size_t(const std::vector<RepairPoint>&, double spacing)>;

  PinchRepair(RefinementState& state, const PinchScan& scan, Operation& operation);

  /// The repair's rounds. Returns the pinches left, counted after the last round's rules.
  std::vector<PinchedTriangle> run(const Drain& drain, const Insert& insert);

  /// Tests: every count after the first is also taken by a full scan, and a difference (in the
  /// pinches, or in any triangle's count) throws std::logic_error.
  void set_count_check(bool on) { check_counts_ = on; }
  /// How many counts were taken from facet changes, and how many of those a full scan checked.
  std::size_t counts_from_changes() const { return counts_from_changes_; }
  std::size_t counts_checked() const { return counts_checked_; }

 private:
  // Counts the pinches into known_: a full scan the first time, then only where pentatopes
  // changed since (from the facet log).
  std::size_t count();
  std::size_t count_from_facet_changes(std::vector<PinchedTriangle>* pinched);
  // Finds a point per pinched triangle of the last count, none closer than `min_spacing` to a
  // feature vertex, and inserts them; returns how many went in.
  std::size_t repair(double min_spacing, const Insert& insert);
  // t's repair point: the surface center of its largest restricted facet, and a pentatope that
  // holds that facet; false when no facet's Voronoi edge crosses ∂Ω.
  bool repair_point_of(const PinchedTriangle& t, Point4* point, delaunay::CellId* hint) const;

  RefinementState& state_;
  const PinchScan& scan_;
  Operation& operation_;
  FacetLog log_;
  bool logging_ = false;                // the facet log is the operations' observer
  std::vector<PinchedTriangle> known_;  // found by the last count, in canonical order
  PinchCounts counts_;                  // every triangle's count, kept from facet changes
  bool check_counts_ = false;
  std::size_t counts_from_changes_ = 0;
  std::size_t counts_checked_ = 0;
};

}  // namespace mesh4d::refine
