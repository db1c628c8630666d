// One step of refinement (docs/algorithm.md, "Refinement"): a bad pentatope's rule applied by
// inserting its point (and, for R5, removing the free vertices near it), then the new
// pentatopes admitted: measured (RefinementState::admit) and queued by their likely rule.
//
// In a parallel phase every lock is taken before the first write, so an operation that meets
// another thread's lock returns Outcome::conflict with nothing written.
#pragma once

#include <array>
#include <shared_mutex>
#include <vector>

#include "delaunay/triangulation.h"
#include "refine/refinement_state.h"
#include "refine/rules.h"
#include "refine/worker.h"

namespace mesh4d::refine {

// exclusive: in periodic time on threads, the regions that a point's copies change lie too close
// together to be claimed apart; nothing was written, and the operation must run alone
// (Worker::exclusive, with every other worker out of its operations).
enum class Outcome { done, skipped, conflict, exclusive };

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
  /// In periodic time, p's three copies go in (PeriodicCovering::copies); skipped for a point
  /// outside the trusted band. In a parallel phase the copies' cavities (and R5's stars) are all
  /// claimed before the first write; Outcome::exclusive where they touch.
  Outcome insert(Worker& w, const Point4& p, delaunay::VertexKind kind, delaunay::CellId hint,
                 Rule rule, const Point4* sample = nullptr, double clearance = -1);
  /// New pentatopes: their info first (the R5 check reads neighbors' infos), then queued.
  void admit(Worker& w, const std::vector<delaunay::CellId>& cells);

 private:
  void enqueue(Worker& w, delaunay::CellId c);
  // The queue (index_of(rule)) of a pentatope that a rule may apply to, or -1.
  int queue_of(delaunay::CellId c) const;
  // Throws BudgetExceeded past the vertex budget, logic_error for a non-finite point.
  void check_budget(const Point4& point) const;
  // The rest of an insertion once its cavity (w.ws->cavity) and, for R5, the free vertices near
  // it (w.near) are claimed: the vertex, the commit, R5's removals, the new pentatopes admitted.
  /// Inserts the point whose cavity is w's, as vertex v (made already), or as a new vertex.
  void commit_insertion(Worker& w, const Point4& point, delaunay::VertexKind kind, Rule rule,
                        mesh4d::VertexId v = delaunay::kNoVertex);
  // Whether the copies' regions (w.region, copy s in [region_end[s], region_end[s + 1])) surely
  // share no pentatope and border none of each other's.
  bool regions_apart(const Worker& w, const std::array<std::size_t, 4>& region_end);
  Outcome insert_one(Worker& w, const Point4& p, delaunay::VertexKind kind, delaunay::CellId hint,
                     Rule rule, const Point4* sample, double clearance);
  Outcome insert_copies(Worker& w, const Point4& p, delaunay::VertexKind kind,
                        delaunay::CellId hint, Rule rule, const Point4* sample, double clearance);
  // insert_copies() beside other threads: every copy's region claimed, then all committed.
  Outcome insert_copies_claimed(Worker& w, const Point4& p, delaunay::VertexKind kind,
                                delaunay::CellId hint, Rule rule, const Point4* sample,
                                double clearance);
  // Where copy `copy` of a point (shifted `periods` periods from the hint's sheet) starts its
  // walk in a parallel phase: a pentatope through the twin of one of the hint's vertices,
  // claimed. kNoCell on a conflict (*none: no such twin).
  delaunay::CellId twin_start(Worker& w, delaunay::CellId hint, int periods, bool* none);
  // R5's removals in periodic time: the live twins, in every sheet, of the vertices removed
  // around p's copies (a copy beyond the covering's end removes nothing there itself).
  void remove_twins(Worker& w, const std::vector<mesh4d::VertexId>& removed);
  // The free vertices of the cavity closer than Δ to p (R5 removes them), into w.near; in a
  // parallel phase their stars are claimed too. False on a conflict.
  bool claim_free_vertices_near(Worker& w, const Point4& p);
  // The same for a cavity of one copy: into `near`, and their stars appended to `region`.
  bool claim_free_vertices_near(Worker& w, const Point4& p, const delaunay::Cavity& cavity,
                                std::vector<mesh4d::VertexId>& near,
                                std::vector<delaunay::CellId>* region);

  RefinementState& state_;
  Rules& rules_;
  FacetObserver* observer_ = nullptr;
  // The covering's map from points to vertices, written by insertions beside other threads.
  std::shared_mutex copies_mutex_;
  // In periodic time on one thread (or alone), a pentatope made by the last insertion in each
  // sheet: where the next copy's walk starts (the hint pentatope lies in one sheet only).
  delaunay::CellId sheet_hint_[3] = {delaunay::kNoCell, delaunay::kNoCell, delaunay::kNoCell};
};

}  // namespace mesh4d::refine
