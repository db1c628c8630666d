// One step of refinement (docs/algorithm.md, "Refinement"): a bad pentatope's rule applied by
// inserting its point (and, for R5, removing the free vertices near it), then the new
// pentatopes admitted: measured (RefinementState::admit) and queued by their likely rule.
//
// In a parallel phase every lock is taken before the first write, so an operation that meets
// another thread's lock returns Outcome::conflict with nothing written.
#pragma once

#include <vector>

#include "delaunay/triangulation.h"
#include "refine/refinement_state.h"
#include "refine/rules.h"
#include "refine/worker.h"

namespace mesh4d::refine {

enum class Outcome { done, skipped, conflict };

// Who needs to know which pentatopes an operation killed and made (the pinch repair's count
// follows the region-boundary facets that changed). Called on the operation's thread, between
// its locks.
class FacetObserver {
 public:
  /// Before anything is written: the pentatopes the operation may kill are w.ws->cavity.cells
  /// and, when `removes`, the stars of the vertices in w.near.
  virtual void before_commit(Worker& w, bool removes) = 0;
  /// After: w.removed holds the vertices it removed, w.fresh (sorted) the new pentatopes.
  virtual void after_commit(Worker& w) = 0;

 protected:
  ~FacetObserver() = default;
};

// A point of ∂Ω to insert outside the rules (the pinch repair's), with a pentatope that
// contained it when it was found.
struct RepairPoint {
  Point4 point;
  Candidate hint;
};

class Operation {
 public:
  Operation(RefinementState& state, Rules& rules);

  void set_observer(FacetObserver* observer) { observer_ = observer; }
  /// Classifies the queued pentatope k and applies its rule (locking its vertices first in a
  /// parallel phase; the caller releases the locks).
  Outcome process(Worker& w, const Candidate& k);
  /// Inserts p (and, for R5, removes the free vertices near it), then admits the new
  /// pentatopes. With `sample` (R1: the surface point whose Δ-ball classify() found free of
  /// feature vertices), that ball (radius `clearance`, Δ when negative) is checked again under
  /// the index's lock, since another thread may have added one since. Outcome::skipped when p
  /// is already a vertex; conflict on another thread's lock or a feature now in the ball.
  /// Throws BudgetExceeded past RefineParams::vertex_budget.
  /// In periodic time, p's three copies go in (PeriodicCovering::copies), one thread only;
  /// skipped for a point outside the trusted band.
  Outcome insert(Worker& w, const Point4& p, delaunay::VertexKind kind, delaunay::CellId hint,
                 Rule rule, const Point4* sample = nullptr, double clearance = -1);
  /// New pentatopes: their info first (the R5 check reads neighbors' infos), then queued.
  void admit(Worker& w, const std::vector<delaunay::CellId>& cells);

 private:
  void enqueue(Worker& w, delaunay::CellId c);
  // The queue (index_of(rule)) of a pentatope that a rule may apply to, or -1.
  int queue_of(delaunay::CellId c) const;
  Outcome insert_one(Worker& w, const Point4& p, delaunay::VertexKind kind, delaunay::CellId hint,
                     Rule rule, const Point4* sample, double clearance);
  Outcome insert_copies(Worker& w, const Point4& p, delaunay::VertexKind kind,
                        delaunay::CellId hint, Rule rule, const Point4* sample, double clearance);
  // R5's removals in periodic time: the live twins, in every sheet, of the vertices removed
  // around p's copies (a copy beyond the covering's end removes nothing there itself).
  void remove_twins(Worker& w, const std::vector<mesh4d::VertexId>& removed);
  // The free vertices of the cavity closer than Δ to p (R5 removes them), into w.near; in a
  // parallel phase their stars are claimed too. False on a conflict.
  bool claim_free_vertices_near(Worker& w, const Point4& p);

  RefinementState& state_;
  Rules& rules_;
  FacetObserver* observer_ = nullptr;
  // In periodic time, a pentatope made by the last insertion in each sheet: where the next
  // copy's walk starts (the hint pentatope lies in one sheet only).
  delaunay::CellId sheet_hint_[3] = {delaunay::kNoCell, delaunay::kNoCell, delaunay::kNoCell};
};

}  // namespace mesh4d::refine
