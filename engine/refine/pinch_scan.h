// Pinches (docs/algorithm.md, "Where labels meet"): a label's region boundary is pinched at a
// triangle when the triangle lies in four or more of the region's boundary tetrahedra, that is,
// when the label occupies two or more separate arcs of the cycle of pentatopes around it.
// These are the read-only scans that find them, in the whole triangulation or around given
// triangles.
#pragma once

#include <array>
#include <utility>
#include <vector>

#include "refine/pinch_counts.h"
#include "refine/refinement_state.h"

namespace mesh4d::refine {

struct PinchedTriangle {
  std::array<mesh4d::VertexId, 3> triangle;              // sorted
  std::vector<std::pair<delaunay::CellId, int>> facets;  // (pentatope, facet index)
};

using Triangle = std::array<mesh4d::VertexId, 3>;

/// The ten triangles of a pentatope, each with its vertices sorted.
std::array<Triangle, 10> triangles_of(const mesh4d::VertexId (&vertices)[5]);

class PinchScan {
 public:
  explicit PinchScan(const RefinementState& state) : state_(state) {}

  /// Every pinch, from a scan of the whole triangulation, on up to RefineParams::threads
  /// threads. With `counts`, also every triangle's count; with `only_if_pinched`, `counts` stays
  /// empty when there is no pinch (the repair then stops, and the table would go unused). In
  /// periodic time only the triangles the covering counts (counts_triangle).
  std::size_t count(std::vector<PinchedTriangle>* pinched, PinchCounts* counts = nullptr,
                    bool only_if_pinched = false) const;
  /// The pentatopes around triangle t, in order, from `start` (which must contain t), and for
  /// each the index of its facet shared with the next.
  void link_cycle(delaunay::CellId start, const std::array<mesh4d::VertexId, 3>& t,
                  std::vector<delaunay::CellId>& cycle, std::vector<int>& crossed) const;
  /// Adds the pinches at triangle t (one per region) found by walking the cycle around it from
  /// `start`, which must contain it.
  void pinches_at(delaunay::CellId start, const std::array<mesh4d::VertexId, 3>& t,
                  std::vector<PinchedTriangle>* pinched) const;
  /// Whether the periodic covering counts triangle t: its lowest vertex lies in the middle
  /// sheet (the others are its copies, or the cut-off ends' artefacts). Always in open time.
  bool counts_triangle(const Triangle& t) const;
  /// Whether pinch p is on a triangle the covering counts.
  bool counted(const PinchedTriangle& p) const { return counts_triangle(p.triangle); }
  /// The pinches on the triangles of these pentatopes.
  std::vector<PinchedTriangle> pinches_on(const std::vector<delaunay::CellId>& cells) const;
  /// By triangle, then label, each one's facets sorted: how a list was found (a full count, the
  /// repair's recount, an update after relabeling) then changes nothing downstream.
  void sort_canonically(std::vector<PinchedTriangle>& pinches) const;

 private:
  // How many threads a read-only scan of `items` uses.
  unsigned scan_parts(std::size_t items) const;

  const RefinementState& state_;
};

}  // namespace mesh4d::refine
