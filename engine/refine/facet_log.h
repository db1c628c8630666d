// The region-boundary facets that operations changed (docs/algorithm.md, "Where labels meet"):
// while the pinch repair runs, each operation logs the boundary facets of the pentatopes it
// killed (−1) and made (+1), so that the repair's next count updates the triangles' counts
// from these changes instead of scanning the whole triangulation.
#pragma once

#include <array>
#include <vector>

#include "refine/operation.h"
#include "refine/refinement_state.h"

namespace mesh4d::refine {

// A region-boundary facet (between pentatopes of different output labels) that appeared (+1)
// or went (−1).
struct FacetChange {
  std::array<mesh4d::VertexId, 4> facet;  // sorted
  domain::Label a, b;                     // its sides' labels
  int delta;
  delaunay::CellId cell;  // for +1: the new pentatope it was seen from
};

class FacetLog final : public FacetObserver {
 public:
  /// One log per worker, for `workers` workers.
  FacetLog(const RefinementState& state, unsigned workers);

  void before_commit(Worker& w, bool removes) override;
  void after_commit(Worker& w) override;
  /// Worker i's changes since the last clear(), in the order they were logged.
  const std::vector<FacetChange>& changes(unsigned i) const { return logs_[i].changes; }
  unsigned workers() const { return static_cast<unsigned>(logs_.size()); }
  void clear();

 private:
  struct DoomedFacet {
    delaunay::CellId cell, other;  // other: the pentatope across it
    FacetChange change;
  };
  struct Log {
    std::vector<FacetChange> changes;
    // The current operation's pentatopes that may die (with the vertex whose removal kills
    // them; kNoVertex: its cavity) and their boundary facets.
    std::vector<std::pair<delaunay::CellId, mesh4d::VertexId>> doomed;
    std::vector<DoomedFacet> doomed_facets;
  };
  // Appends c's region-boundary facets (c's side first) as (c, other, change) to `out`.
  void boundary_facets_of(delaunay::CellId c, int delta, std::vector<DoomedFacet>& out) const;
  // Drops the pairs of changes[first..] that cancel (a facet that went and came back between
  // the same labels).
  static void cancel_opposite_changes(std::vector<FacetChange>& changes, std::size_t first);

  const RefinementState& state_;
  std::vector<Log> logs_;
};

}  // namespace mesh4d::refine
