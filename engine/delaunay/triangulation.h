// A 4D Delaunay triangulation: point location, Bowyer–Watson insertion and vertex removal, with
// exact predicates and a symbolic tie-break, so that every pentatope is positively oriented and
// the triangulation is the unique Delaunay triangulation of its vertices under the perturbation
// of predicates.h (docs/algorithm.md, "Kernel").
//
// The convex hull is closed by an infinite vertex (id 0), as in CGAL: each hull facet forms an
// infinite pentatope with it. Orientation of an infinite pentatope: a point beyond its hull facet,
// put in the infinite vertex's slot, gives orient4 > 0.
//
// Insertion is split in three steps that a parallel refiner can run apart: locate a pentatope in
// conflict, compute the cavity (reading the mesh, writing only visit stamps), then commit it.
// Each step has a form for concurrent use: a Workspace per thread (scratch, walk state, a
// pentatope allocator) and a CellGuard that claims each pentatope before it is read
// (cell_guard.h); a refusal stops the step with nothing written.
#pragma once

#include <atomic>
#include <span>
#include <vector>

#include "delaunay/cell_guard.h"
#include "delaunay/conflict_filter.h"
#include "delaunay/pentatope_store.h"
#include "delaunay/ridge_table.h"

namespace mesh4d::delaunay {

struct FillCell;

/// The pentatopes whose circumsphere contains a point, and the facets that bound them.
struct Cavity {
  struct Facet {
    CellId cell;  // a pentatope of the cavity
    int index;    // the facet opposite cell.v[index] borders a pentatope outside the cavity
  };
  std::vector<CellId> cells;
  std::vector<Facet> boundary;
};

class Triangulation {
 public:
  /// What one thread needs to insert and remove: scratch that is reused, the walk's random
  /// state, and where its new pentatopes' slots come from.
  struct Workspace {
    explicit Workspace(CellAllocator* allocator) : cells(allocator) {}
    Cavity cavity;
    std::vector<CellId> created;
    RidgeTable ridges;
    static constexpr std::uint64_t kWalkSeed = 0x9e3779b97f4a7c15ull;
    std::uint64_t walk_rng = kWalkSeed;
    CellAllocator* cells;
  };

  /// block_shift sizes the storage blocks (2^block_shift pentatopes each).
  explicit Triangulation(unsigned block_shift = 16);
  /// Empty again, keeping the storage for reuse (vertex removal's local triangulations).
  void reset();

  struct InsertResult {
    VertexId vertex;  // the new vertex, or the existing one at the same point
    bool inserted;    // false when the point equals an existing vertex (nothing changed)
    CellId cell;      // a pentatope incident to the vertex: a good hint for the next insertion
  };

  /// Inserts p (finite coordinates required). Until five affinely independent points exist the
  /// vertices wait without pentatopes; the triangulation then forms at once.
  InsertResult insert(const Point4& p, VertexKind kind = VertexKind::free, CellId hint = kNoCell);

  /// Inserts points in a spatially coherent (Hilbert/BRIO) order; returns their vertex ids in
  /// the order of `points`.
  std::vector<VertexId> insert_all(std::span<const Point4> points,
                                   VertexKind kind = VertexKind::free);

  /// Removes a vertex that is not on the convex hull and re-triangulates the hole with the
  /// Delaunay triangulation of its link (older vertices first). Returns false, changing nothing,
  /// for the infinite vertex, a removed vertex, or a hull vertex. Feature vertices are the
  /// caller's to protect. The pentatopes that fill the hole are appended to `created` if given.
  bool remove(VertexId v, std::vector<CellId>* created = nullptr);

  enum class RemoveResult { removed, refused, conflict };
  /// remove() for concurrent use: `conflict` when the guard refused a pentatope of the star
  /// (nothing changed), `refused` where remove() returns false.
  RemoveResult remove(VertexId v, std::vector<CellId>* created, Workspace& ws, CellGuard* guard);

  /// Lets `filter` answer the in-sphere questions of cavity searches first (nullptr: none). Its
  /// owner keeps it current for every live pentatope a search can reach: it is set once every
  /// pentatope has its ball, and each operation's new pentatopes get theirs before any other
  /// search reaches them.
  void set_conflict_filter(const ConflictFilter* filter) { filter_ = filter; }

  // --- The three steps of an insertion ------------------------------------------------------

  /// A pentatope that contains p in its closure (finite), or an infinite pentatope whose hull
  /// facet sees p strictly from outside. Walks from `hint` (any live pentatope, or kNoCell).
  CellId locate(const Point4& p, CellId hint) const;
  /// locate() for concurrent use: `hint` must be claimed by the caller; each pentatope the walk
  /// enters is claimed first. kNoCell when the guard refused one.
  CellId locate(const Point4& p, CellId hint, Workspace& ws, CellGuard* guard) const;

  /// Whether the pentatope's (perturbed) circumsphere contains the point p with id pid.
  bool in_conflict(CellId c, const Point4& p, VertexId pid) const;
  /// in_conflict() of `count` (at most 5) pentatopes into conflict[0..count): the conflict
  /// filter's certain answers first, if one is set, then the finite ones four at a time through
  /// the batched in-sphere filter: the same answers.
  void conflicts(const CellId* cells, int count, const Point4& p, VertexId pid,
                 bool* conflict) const;

  /// Fills `cavity` with the conflict region of p (id pid) grown from `start`, which must be in
  /// conflict. Stamps visited pentatopes; changes nothing else.
  void find_cavity(const Point4& p, VertexId pid, CellId start, Cavity& cavity);
  /// find_cavity() for concurrent use: `start` must be claimed by the caller, and every other
  /// pentatope it tests is claimed first; false when the guard refused one.
  bool find_cavity(const Point4& p, VertexId pid, CellId start, Cavity& cavity, CellGuard* guard);

  /// Replaces the cavity by the star of vertex pid. Returns one new pentatope.
  CellId commit(const Cavity& cavity, VertexId pid) { return commit(cavity, pid, own_); }
  CellId commit(const Cavity& cavity, VertexId pid, Workspace& ws);

  /// A vertex for a concurrent insertion (its id orders it by age), locked by `owner`; counted
  /// in number_of_vertices(). discard_vertex() undoes it when the insertion rolls back.
  VertexId new_vertex(const Point4& p, VertexKind kind, std::uint32_t owner);
  /// new_vertex() for each point, with consecutive ids (the first returned): in periodic time a
  /// point's copies, which ties between cospherical points must order alike in every sheet.
  VertexId new_vertices(std::span<const Point4> points, VertexKind kind, std::uint32_t owner);
  void discard_vertex(VertexId v);

  /// Stamps run low after some 2·10⁹ cavity searches; a parallel phase checks this before each
  /// operation and stops, and clear_stamps() (one thread) makes room again.
  bool stamps_running_low() const {
    return stamp_.load(std::memory_order_relaxed) >= kStampLimit - (1u << 24);
  }
  void clear_stamps();
  /// Prepares the storage for concurrent insertion of up to `max_vertices` vertex ids.
  void prepare_concurrent(std::size_t max_vertices) { store_.prepare_concurrent(max_vertices); }
  /// Takes a worker's allocator back (its free slots, its count) once the workers stopped.
  void merge(Workspace& ws) { store_.merge(*ws.cells); }

  // --- Queries -----------------------------------------------------------------------------

  /// 4 once the first pentatope exists, -1 before.
  int dimension() const { return dimension_; }
  /// Vertices in the triangulation (not the infinite one, pending or removed ones).
  std::size_t number_of_vertices() const { return vertex_count_.load(std::memory_order_relaxed); }
  std::size_t number_of_cells() const { return store_.live_cells(); }
  std::size_t number_of_finite_cells() const;
  const PentatopeStore& store() const { return store_; }
  /// For the vertex locks' words (VertexLocks); the combinatorics change only through the
  /// operations above.
  PentatopeStore& store() { return store_; }
  /// The workspace of the single-threaded operations.
  Workspace& workspace() { return own_; }
  /// A live pentatope, or kNoCell while dimension() < 4.
  CellId any_cell() const { return any_cell_.load(std::memory_order_relaxed); }

  /// The pentatopes incident to vertex v (its star), v in the triangulation.
  void incident_cells(VertexId v, std::vector<CellId>& cells) const {
    collect_star(v, cells, nullptr);
  }
  /// The same, claiming each pentatope first (v must be held); false when one was refused.
  bool incident_cells(VertexId v, std::vector<CellId>& cells, CellGuard* guard) const {
    return collect_star(v, cells, guard);
  }

  /// The exact pentatope orientation with point p in slot i (p replacing v[i]).
  int orient_with(CellId c, int i, const Point4& p) const;

 private:
  InsertResult insert_pending(const Point4& p, VertexKind kind);
  void try_build_initial_simplex();
  void build_initial_simplex(VertexId b[5]);
  void insert_vertex_into_mesh(VertexId v, CellId hint, CellId* last);
  // The star of v; false when the guard (if any) refused one of its pentatopes.
  bool collect_star(VertexId v, std::vector<CellId>& star, CellGuard* guard) const;
  // remove()'s fill when gift-wrapping cannot prove its own: the pentatopes of the Delaunay
  // triangulation of v's link that conflict with v (neighbors not set).
  void fill_from_link_triangulation(VertexId v, const std::vector<VertexId>& link,
                                    std::vector<FillCell>& fill) const;
  std::uint32_t next_stamp();

  static constexpr std::uint32_t kStampLimit = 0xFFFFFFF0u;

  PentatopeStore store_;
  int dimension_ = -1;
  std::atomic<std::size_t> vertex_count_{0};
  std::atomic<CellId> any_cell_{kNoCell};
  std::vector<VertexId> pending_;  // vertices waiting for the first simplex
  // Visit stamps: from one counter shared by all threads, so that no two searches share one.
  std::atomic<std::uint32_t> stamp_{0};
  const ConflictFilter* filter_ = nullptr;
  mutable Workspace own_;  // the single-threaded operations' (locate's walk state is mutable)
};

}  // namespace mesh4d::delaunay
