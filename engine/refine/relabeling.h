// Closing the pinches that the repair leaves, by relabeling (docs/algorithm.md, "Where labels
// meet").
//
// Around a triangle t the pentatopes form a cycle; a label's region is pinched at t when it
// occupies two or more separate arcs of that cycle (link_labels.h). Where three labels meet at
// a sharp junction (the time caps, the valve plane), inserting more surface points there does
// not converge: each new point makes new small pentatopes whose circumcenters again fall on
// alternating sides. Moving the pentatopes of the shorter arcs (or of the gaps between them) to
// a neighboring label joins the arcs. A move is allowed only when the moved pentatope has its
// five vertices on ∂Ω (so every boundary tetrahedron still does, now and after later changes
// around it), and a pentatope that enters the output meets the quality bounds; the
// triangulation itself does not change. The moved pentatopes are the exception to "the label
// of a pentatope is the label at its circumcenter"; RefineResult::relabeled counts them.
#pragma once

#include <vector>

#include "refine/operation.h"
#include "refine/pinch_scan.h"

namespace mesh4d::refine {

/// Whether pentatope c, which already carries its new label, may have moved there from label
/// `from`: its five vertices on ∂Ω, and one that enters the output meets the quality bounds.
bool may_relabel(const RefinementState& state, delaunay::CellId c, domain::Label from);

class Relabeling {
 public:
  /// Removals of free vertices admit their new pentatopes to worker w's queues.
  Relabeling(RefinementState& state, const PinchScan& scan, Operation& operation, Worker& w);

  /// The pinches now: counted again only when something changed since they were known.
  const std::vector<PinchedTriangle>& current_pinches();
  /// Makes `pinches` the current list (they were just counted).
  void set_current(std::vector<PinchedTriangle> pinches);
  /// Pentatopes changed: the current list must be counted again.
  void invalidate() { current_known_ = false; }
  /// Moves a few pentatopes to a neighboring label where that lowers the count of pinches;
  /// returns how many moved.
  std::size_t relabel_pinches();
  /// Removes the free vertices of the pentatopes around the pinched triangles (they stop the
  /// relabeling there: a moved pentatope would put them on the boundary); returns how many.
  std::size_t remove_free_vertices_at_pinches();

 private:
  struct Move {
    delaunay::CellId cell;
    domain::Label to;
  };
  struct MoveSearch {
    std::vector<Move> best;  // the moves with the largest positive gain so far
    long best_gain = 0;
    int budget = 4096;  // gains still to evaluate
  };
  // The ways to join every label's arcs around a pinched triangle.
  std::vector<std::vector<Move>> relabel_options(const PinchedTriangle& p) const;
  // How many pinches the moves remove (negative: add); the least long when one is not allowed.
  long relabel_gain(const std::vector<Move>& moves);
  bool movable(delaunay::CellId c, domain::Label from) const;
  // Tries `base` extended by each way to join the labels around the pinches it leaves on its
  // pentatopes' triangles, recursively to `depth` more levels.
  void extend_moves(const std::vector<Move>& base, int depth, MoveSearch& search);
  std::vector<domain::Label> apply(const std::vector<Move>& moves);  // returns the old labels
  void undo(const std::vector<Move>& moves, const std::vector<domain::Label>& before);

  RefinementState& state_;
  const PinchScan& scan_;
  Operation& operation_;
  Worker& worker_;
  std::vector<bool> shifted_;             // by cell: moved without lowering the count
  std::vector<PinchedTriangle> current_;  // valid while current_known_
  bool current_known_ = false;            // no pentatope or label changed since they were counted
};

}  // namespace mesh4d::refine
