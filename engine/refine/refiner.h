// Sequential Delaunay refinement of a 4D image (Foteinos & Chrisochoides; ALGORITHM.md,
// "Refinement").
//
// All five rules (R1 to R5, R3 first by default) and an interior sizing bound; picking regions
// for R4 and R5 measure the cavity of each trial point before choosing. Each pentatope's
// circumball is computed once, when it is made, and its label once, when first read (CellInfo);
// with a bound on its rounding, the ball also answers most in-sphere questions of the cavity
// searches (delaunay/conflict_filter.h).
// Where labels meet, the paper's guarantee (for one label) does not hold: a bounded pinch repair
// (refiner_junctions.cpp) samples ∂Ω where a region's boundary is not a manifold, and what it
// leaves is closed by moving a few pentatopes whose vertices all lie on ∂Ω to a neighboring label
// (refiner_relabel.cpp). With RefineParams::threads > 1 the rules run on worker threads sharing the
// triangulation (refiner_parallel.cpp); the repair and relabeling between those phases stay on one
// thread.
#pragma once

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <shared_mutex>
#include <string>
#include <vector>

#include "delaunay/chunked_array.h"
#include "delaunay/geometry.h"
#include "delaunay/triangulation.h"
#include "delaunay/vertex_locks.h"
#include "domain/surface_oracle.h"
#include "mesh/mesh4.h"
#include "mesh/mesh_stats.h"
#include "refine/block_stack.h"
#include "refine/feature_index.h"
#include "refine/pinch_counts.h"
#include "refine/progress.h"
#include "refine/reader_biased_mutex.h"
#include "refine/refine_params.h"

namespace mesh4d::refine {

struct RefineResult {
  mesh::Mesh4 mesh;
  mesh::MeshStats stats;
  std::vector<std::string> warnings;
  // Pentatopes given a neighbor's label to close a pinch (refiner_relabel.cpp): their
  // circumcenter lies in another label, within their small circumball of the junction.
  std::size_t relabeled = 0;
  // The parallel phases' overheads (Progress): all 0 with one thread.
  std::uint64_t rollbacks = 0;
  double contention_seconds = 0;
  double idle_seconds = 0;
  double rules_seconds = 0;  // spent applying the rules (the part that runs on the workers)
  // The pinch repair's rounds, the rules after each included (on the patients it took up to
  // two thirds of the time in session 12).
  double repair_seconds = 0;
};

class Refiner final : private delaunay::ConflictFilter {
 public:
  /// Validates the parameters (ParamError). The oracle must outlive the refiner.
  Refiner(const domain::SurfaceOracle& oracle, const RefineParams& params);

  /// Refines until no rule applies, then extracts the mesh. Throws Cancelled when the sink asks
  /// to stop and BudgetExceeded past the vertex budget.
  RefineResult run(ProgressSink* sink = nullptr);

  /// The triangulation (for the validity checker in tests).
  const delaunay::Triangulation& triangulation() const { return tri_; }
  /// Tests: every pinch count of the repair after its first is also taken by a full scan, and
  /// a difference (in the pinches, or in any triangle's count) throws std::logic_error.
  void set_pinch_count_check(bool on) { check_counts_ = on; }
  /// Tests: every repair point skipped as refused in an earlier round is computed again, and
  /// one that would now differ or go in throws std::logic_error; counts those checks.
  void set_refused_point_check(bool on) { check_refused_ = on; }
  std::size_t refused_points_rechecked() const { return refused_rechecked_; }

 private:
  struct Candidate {
    delaunay::CellId cell;
    mesh4d::VertexId v[5];  // to recognize a reused cell id
  };
  enum Rule { kR1, kR2, kR3, kR4, kR5, kSizing, kNone };
  // A region-boundary facet (between pentatopes of different output labels) that appeared
  // (+1) or went (−1).
  struct FacetChange {
    std::array<mesh4d::VertexId, 4> facet;  // sorted
    domain::Label a, b;                     // its sides' labels
    int delta;
    delaunay::CellId cell;  // for +1: the new pentatope it was seen from
  };
  struct DoomedFacet {
    delaunay::CellId cell, other;  // other: the pentatope across it
    FacetChange change;
  };
  // What one thread of refinement owns. The single-threaded rules use worker 0 without locks;
  // in a parallel phase each thread has one, with its own workspace, locks and queues.
  struct Worker {
    Worker(delaunay::Triangulation& tri, unsigned id, std::uint64_t seed)
        : index(id), locks(tri.store(), id + 1), rng(seed) {}
    unsigned index;
    delaunay::CellAllocator cells;  // its pentatope slots in a parallel phase
    delaunay::Triangulation::Workspace own_ws{&cells};
    delaunay::Triangulation::Workspace* ws = nullptr;  // own_ws, or the triangulation's
    delaunay::VertexLocks locks;
    delaunay::CellGuard* guard = nullptr;  // &locks in a parallel phase
    bool conflict = false;                 // the current operation met another thread's lock
    Point4 r1_sample{};                    // classify()'s R1 surface point, before pinpointing
    std::mt19937_64 rng;                   // of the picking regions
    delaunay::Cavity trial;                // trial cavities of the picking regions
    std::vector<delaunay::CellId> fresh, created, star;
    std::vector<mesh4d::VertexId> near;
    // While the repair counts pinches from facet changes (counting_facets_): the changes this
    // worker's operations made, and the current operation's pentatopes that may die (with the
    // vertex whose removal kills them; kNoVertex: its cavity) and their boundary facets.
    std::vector<FacetChange> facet_changes;
    std::vector<std::pair<delaunay::CellId, mesh4d::VertexId>> doomed;
    std::vector<DoomedFacet> doomed_facets;
    std::vector<mesh4d::VertexId> removed;            // of near, by the current operation
    std::mutex queue_mutex;                           // the queues, which thieves also take from
    std::array<BlockStack<Candidate>, kNone> queues;  // one stack per rule
    std::vector<std::pair<Candidate, Rule>> retry;    // rolled back; again when the queues run dry
    std::uint64_t operations = 0;
    unsigned consecutive_rollbacks = 0;
    // Counters, read by the reporting thread while this one writes them.
    std::array<std::atomic<std::uint64_t>, 5> insertions{}, removals{};
    std::atomic<std::uint64_t> rollbacks{0}, contention_ns{0}, idle_ns{0};
    std::atomic<std::int64_t> live_cells{0};  // cells.live, published after each operation
    // For the other workers' R5 gate (Refiner::pop, Refiner::work), each on a cache line of its
    // own: its queues' lengths (written under queue_mutex) and whether it runs an operation of
    // a rule other than R5. Counters shared by all workers made every pop, push and operation
    // write one line that every core then had to fetch back.
    alignas(64) std::array<std::atomic<std::int64_t>, kNone> queued{};
    alignas(64) std::atomic<bool> higher_in_flight{false};
    // After changing queues[r]: under queue_mutex in a parallel phase.
    void publish_length(int r) {
      queued[r].store(static_cast<std::int64_t>(queues[r].size()), std::memory_order_relaxed);
    }
  };
  enum class Outcome { done, skipped, conflict };
  // What every rule asks of a pentatope, computed once when it is created: its circumball (in
  // admit(), for each new cell: slots are reused), and the label at its center when first read.
  // Every live pentatope has one, the infinite ones too (not finite): a neighbor's info says
  // whether it is infinite without a load of its record (the loads of neighbors' records were most
  // of find_restricted_facet's time). 64 bytes, aligned: one cache line each (neighbors' infos are
  // read in every classification).
  struct alignas(64) CellInfo {
    Point4 center;
    double radius = 0;
    double surface_lower = 0;         // a lower bound on the distance from center to ∂Ω
    std::uint32_t surface_voxel = 0;  // where the cfp of center starts (PointFacts)
    // Circumball::center_error rounded up: the cavity searches' in-sphere filter (decide()).
    float center_error = 0;
    // The label at the center plus one, 0 until asked (label_of): most new pentatopes die before
    // anything reads it. Atomic (std::atomic_ref) where read: a thread classifying a neighbor
    // may compute it.
    mutable std::uint32_t label_code = 0;
    bool finite = false;  // false for infinite or flat pentatopes
    // Radius over shortest edge ≥ ρ̄ (R3 where inside), measured with the center: the vertices
    // are loaded once per new pentatope.
    bool long_radius = false;
    // Whether surface_lower and surface_voxel are set: only once the pentatope is classified
    // (six in ten pentatopes die before, on the ventricle and the patients).
    bool surface_known = false;
  };
  static_assert(sizeof(CellInfo) == 64, "one cache line per pentatope's info");

  delaunay::Simplex4 simplex_of(delaunay::CellId c) const {
    delaunay::Simplex4 s;
    for (int i = 0; i < 5; ++i) s[i] = tri_.store().point(tri_.store().cell(c).v[i]);
    return s;
  }
  Point4 centroid_of(delaunay::CellId c) const {
    Point4 g{};
    for (const Point4& p : simplex_of(c))
      for (int k = 0; k < 4; ++k) g[k] += 0.2 * p[k];
    return g;
  }
  void insert_box();
  // Feature vertices on every triple junction, RefineParams::junction_spacing · Δ apart.
  void insert_junctions();
  // New pentatopes: their info first (the R5 check reads neighbors' infos), then queued.
  void admit(Worker& w, const std::vector<delaunay::CellId>& cells);
  void admit(const std::vector<delaunay::CellId>& cells) { admit(*workers_[0], cells); }
  // Their CellInfo (not yet the label: label_of()).
  void update_infos(const std::vector<delaunay::CellId>& cells);
  // ConflictFilter: the in-sphere questions of cavity searches, answered from the infos'
  // circumballs where rounding cannot change the answer. Set once every pentatope has its info
  // (run()); each operation admits its new pentatopes before any other search can reach them.
  void decide(const delaunay::CellId* cells, int count, const Point4& p,
              std::int8_t* verdict) const override;
  void prefetch(const delaunay::CellId* cells, int count) const override {
    for (int k = 0; k < count; ++k) __builtin_prefetch(&info_[cells[k]]);
  }
  void enqueue(Worker& w, delaunay::CellId c);
  bool has_restricted_non_feature_facet(delaunay::CellId c) const;
  Rule quick_rule(delaunay::CellId c) const;  // a cheap priority guess, confirmed when popped
  bool still_valid(const Candidate& k) const;
  // Decides what to do with a live pentatope: the rule that applies and the point to insert.
  Rule classify(Worker& w, delaunay::CellId c, Point4* point, delaunay::VertexKind* kind);
  Point4 pick_from_region(Worker& w, delaunay::CellId c, const Point4& center, double radius);
  bool find_restricted_facet(delaunay::CellId c, Point4* surface_center,
                             double* surface_radius) const;
  Point4 pick_on_surface(Worker& w, delaunay::CellId c, const Point4& z, double radius);
  // -1 for a point equal to a vertex; sets w.conflict (and returns -1) on another's lock.
  double worst_new_quality(Worker& w, const Point4& p, delaunay::CellId hint);
  // The free vertices of the cavity closer than Δ to p (R5 removes them), into w.near; in a
  // parallel phase their stars are claimed too. False on a conflict.
  bool claim_free_vertices_near(Worker& w, const Point4& p);
  // Whether a feature vertex lies within r of p (the index is shared by the workers). With
  // `own_cell_only`, only those in p's cell of the index: a true answer, or perhaps a missed one.
  bool feature_within(const Point4& p, double r, bool own_cell_only = false) const {
    std::shared_lock lock(features_mutex_);
    return own_cell_only ? features_.any_within_own_cell(p, r) : features_.any_within(p, r);
  }
  // Whether no point of segment [a, b] can be an R1 point of pentatope c: the part inside its
  // circumball (if any) lies strictly within Δ of one feature vertex. False may be a missed
  // one: only the pentatope's own vertices and one cell of the index are tried.
  bool cfp_dismissed(delaunay::CellId c, Point4 a, Point4 b) const;
  // Whether pentatope c's circumball meets ∂Ω, judged at the cfp of its center; for a ball
  // smaller than 2Δ, also false where the cfp is sure to be within Δ of a feature vertex.
  bool ball_meets_surface(delaunay::CellId c, domain::SurfaceBracket* cfp) const;
  Point4 clamp_to_box(const Point4& p) const;
  // Applies the rules until none does: on this thread, or on RefineParams::threads workers.
  void drain(ProgressSink* sink);
  void drain_sequential(ProgressSink* sink);
  void drain_parallel(ProgressSink* sink);
  // A parallel phase's frame: storage and workers ready, each worker on its own workspace and
  // locks; then, after the threads joined, their pentatopes merged back for serial work.
  void enter_parallel(unsigned threads);
  void leave_parallel(unsigned threads);
  // One thread of a parallel phase (refiner_parallel.cpp).
  struct Shared;
  void work(Worker& w, Shared& shared, ProgressSink* sink);
  bool pop(Worker& w, Shared& shared, Candidate* k, Rule* rule);
  // Takes the older half of another worker's queues (of one rule only, unless kNone).
  bool steal(Worker& w, Shared& shared, Rule only = kNone);
  bool queued_anywhere(const Shared& shared, Rule rule) const;  // in any worker's queues
  bool higher_in_flight(const Shared& shared) const;  // an R1–R4 operation under way anywhere
  void distribute_work(unsigned threads);             // all queued work split among the workers
  // Pops and applies one candidate: locks its pentatope (in a parallel phase), classifies it,
  // inserts the rule's point. The caller releases the locks.
  Outcome process(Worker& w, const Candidate& k);
  // Counts the pinched triangles (a triangle in four or more of a label's region boundary
  // tetrahedra, seen where three labels meet) into known_pinches_: a full scan the first time,
  // then only where pentatopes changed since.
  std::size_t count_for_repair();
  // Inserts surface points around the pinches of the last count, none closer than
  // `min_spacing` to a feature vertex; returns how many.
  std::size_t repair_pinches(double min_spacing);
  struct RepairPoint {
    Point4 point;
    Candidate hint;  // a pentatope that contained it when it was found
  };
  // Inserts the repair's points (those not within `min_spacing` of a feature vertex), on the
  // job's threads where there are enough of them; returns how many went in.
  std::size_t insert_repair_points(const std::vector<RepairPoint>& points, double min_spacing);
  struct PinchedTriangle {
    std::array<mesh4d::VertexId, 3> triangle;              // sorted
    std::vector<std::pair<delaunay::CellId, int>> facets;  // (pentatope, facet index)
  };
  // A pinched triangle's repair point that lay within the spacing of a feature vertex, and
  // what it was computed from: per facet, its pentatope's and the neighbor's vertices (in
  // order: a pentatope made again from them has the same circumcenter). While they hold, the
  // point is the same and still refused (feature vertices are never removed), so later rounds
  // at that spacing skip it (Pat05 at the paper's spacing: late rounds refused nearly all of
  // about 1,300 points each).
  struct RefusedPoint {
    Point4 point;
    double spacing;
    std::vector<delaunay::CellId> neighbors;
    std::vector<mesh4d::VertexId> vertices;
  };
  // t's repair point: the surface center of its largest restricted facet, and a pentatope
  // that holds that facet; false when no facet's Voronoi edge crosses ∂Ω.
  bool repair_point_of(const PinchedTriangle& t, Point4* point, delaunay::CellId* hint) const;
  // Whether `refused` still describes the facets of `t` (the same pentatopes, neighbors).
  bool still_refused(const PinchedTriangle& t, const RefusedPoint& refused, double spacing) const;
  // How many threads a read-only scan of `items` between parallel phases uses.
  unsigned scan_parts(std::size_t items) const;
  // Every pinch, from a scan of the whole triangulation.
  // With `counts`, also fills it with every triangle's count.
  // With `only_if_pinched`, `counts` stays empty when there is no pinch (the repair stops then,
  // and the table would go unused: a single label, the hypersphere's case).
  std::size_t count_pinches(std::vector<PinchedTriangle>* pinched, PinchCounts* counts = nullptr,
                            bool only_if_pinched = false) const;
  // The same count after a full one, from pinch_counts_ updated with the facet changes that
  // operations logged since: only the pinched triangles are walked. (Until session 11 every
  // triangle of every region-boundary facet of a pentatope made since was walked: a sixth of
  // the time on the patients.)
  std::size_t count_from_facet_changes(std::vector<PinchedTriangle>* pinched);
  // An operation's part in that log: before it commits, the boundary facets of the pentatopes
  // it may kill (the cavity, and for R5 the stars of the vertices it may remove); after it,
  // those of the ones that died (−1) and of the new ones (+1).
  void note_doomed_facets(Worker& w, int rule);
  void log_facet_changes(Worker& w);
  // Drops the pairs of changes[first..] that cancel (a facet that went and came back between
  // the same labels).
  static void cancel_opposite_changes(std::vector<FacetChange>& changes, std::size_t first);
  // Appends c's region-boundary facets (c's side first) as (c, other, change) to `out`.
  void boundary_facets_of(delaunay::CellId c, int delta, std::vector<DoomedFacet>& out) const;
  // The pentatopes around triangle t, in order, from `start` (which must contain t), and for
  // each the index of its facet shared with the next.
  void link_cycle(delaunay::CellId start, const std::array<mesh4d::VertexId, 3>& t,
                  std::vector<delaunay::CellId>& cycle, std::vector<int>& crossed) const;
  // The label at a finite pentatope's circumcenter (or the one relabeling gave it), computed
  // on the first request. Two threads may compute it at once: they store the same value.
  domain::Label label_of(delaunay::CellId c) const {
    const CellInfo& info = info_[c];
    std::atomic_ref<std::uint32_t> code(info.label_code);
    std::uint32_t k = code.load(std::memory_order_relaxed);
    if (k == 0) {
      k = std::uint32_t{oracle_.label_at(info.center)} + 1;
      code.store(k, std::memory_order_relaxed);
    }
    return static_cast<domain::Label>(k - 1);
  }
  void set_label(delaunay::CellId c, domain::Label label) {
    info_[c].label_code = std::uint32_t{label} + 1;
  }
  // The label a pentatope has in the output (0: not output).
  domain::Label output_label(delaunay::CellId c) const { return info_[c].finite ? label_of(c) : 0; }
  // Closes the pinches the repair left by moving a few pentatopes, all of whose vertices lie on
  // ∂Ω, to a neighboring label (refiner_relabel.cpp); returns how many pentatopes moved.
  std::size_t relabel_pinches();
  // The pinches now: counted again only when something changed since the last time (a full
  // count costs as much as a twentieth of the ventricle's refinement).
  const std::vector<PinchedTriangle>& current_pinches();
  // Makes `pinches` the current list, in canonical order: by triangle, then label, each one's
  // facets sorted. How a list was found (a full count, the repair's recount, an update after
  // relabeling) then changes nothing downstream.
  void set_current_pinches(std::vector<PinchedTriangle> pinches);
  // That order: by triangle, then label, each one's facets sorted.
  void sort_canonically(std::vector<PinchedTriangle>& pinches) const;
  // Removes the free vertices of the pentatopes around the pinched triangles; returns how many.
  std::size_t remove_free_vertices_at_pinches();
  struct Move {
    delaunay::CellId cell;
    domain::Label to;
  };
  // The ways to join every label's arcs around a pinched triangle.
  std::vector<std::vector<Move>> relabel_options(const PinchedTriangle& p) const;
  // How many pinches the moves remove (negative: add); the least long when one is not allowed.
  long relabel_gain(const std::vector<Move>& moves);
  bool movable(delaunay::CellId c, domain::Label from) const;
  struct MoveSearch {
    std::vector<Move> best;  // the moves with the largest positive gain so far
    long best_gain = 0;
    int budget = 4096;  // gains still to evaluate
  };
  // Tries `base` extended by each way to join the labels around the pinches it leaves on its
  // pentatopes' triangles, recursively to `depth` more levels.
  void extend_moves(const std::vector<Move>& base, int depth, MoveSearch& search);
  std::vector<domain::Label> apply(const std::vector<Move>& moves);  // returns the old labels
  void undo(const std::vector<Move>& moves, const std::vector<domain::Label>& before);
  // The pinches on the triangles of these pentatopes.
  std::vector<PinchedTriangle> pinches_on(const std::vector<delaunay::CellId>& cells) const;
  // Adds the pinches at triangle t (one per region) found by walking the cycle of pentatopes
  // around it from `start`, which must contain it.
  void pinches_at(delaunay::CellId start, const std::array<mesh4d::VertexId, 3>& t,
                  std::vector<PinchedTriangle>* pinched) const;
  // Inserts p (and, for R5, removes the free vertices near it), then admits the new
  // pentatopes. With `sample` (R1: the surface point whose Δ-ball classify() found free of
  // feature vertices), that ball (radius `clearance`, Δ when negative) is checked again under
  // the index's lock, since another thread may have added one since. Outcome::skipped when p is
  // already a vertex; conflict on another thread's lock or a feature now in the ball (nothing
  // written then).
  Outcome insert_and_admit(Worker& w, const Point4& p, delaunay::VertexKind kind,
                           delaunay::CellId hint, int rule, const Point4* sample = nullptr,
                           double clearance = -1);
  void report(ProgressSink* sink, Phase phase, bool force);
  Progress totals() const;  // the workers' counters summed
  mesh::Mesh4 extract(std::vector<std::string>& warnings) const;

  const domain::SurfaceOracle& oracle_;
  RefineParams params_;
  delaunay::Triangulation tri_;
  delaunay::ChunkedArray<CellInfo> info_;  // by cell id; blocks never move (parallel phases)
  std::array<Point4, 2> box_;
  std::vector<std::unique_ptr<Worker>> workers_;  // [0] also serves single-threaded work
  bool concurrent_ready_ = false;                 // storage prepared for parallel phases
  FeatureIndex features_;
  mutable ReaderBiasedMutex features_mutex_;
  std::vector<PinchedTriangle> known_pinches_;  // found by the last pinch count
  // The last repair round's refused points, by their triangle's facets (still_refused()).
  std::map<std::vector<std::pair<delaunay::CellId, int>>, RefusedPoint> refused_;
  // From the repair's first count to its end: counts kept from facet changes, which
  // insert_and_admit() logs meanwhile (count_from_facet_changes).
  bool counting_facets_ = false;
  PinchCounts pinch_counts_;
  bool check_counts_ = false;   // set_pinch_count_check()
  bool check_refused_ = false;  // set_refused_point_check()
  std::size_t refused_rechecked_ = 0;
  std::vector<bool> shifted_;  // by cell: moved by relabel_pinches() without lowering the count
  std::vector<PinchedTriangle> current_pinches_;  // valid while pinches_current_
  bool pinches_current_ = false;  // no pentatope or label changed since they were counted
  Progress progress_;
  std::chrono::steady_clock::time_point start_, last_report_;
  double rules_seconds_ = 0;
};

}  // namespace mesh4d::refine
