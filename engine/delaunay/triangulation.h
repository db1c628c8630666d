// A 4D Delaunay triangulation: point location, Bowyer–Watson insertion and vertex removal, with
// exact predicates and a symbolic tie-break, so that every pentatope is positively oriented and
// the triangulation is the unique Delaunay triangulation of its vertices under the perturbation
// of predicates.h (ALGORITHM.md, "Kernel").
//
// The convex hull is closed by an infinite vertex (id 0), as in CGAL: each hull facet forms an
// infinite pentatope with it. Orientation of an infinite pentatope: a point beyond its hull facet,
// put in the infinite vertex's slot, gives orient4 > 0.
//
// Insertion is split in three steps that a parallel refiner can run apart: locate a pentatope in
// conflict, compute the cavity (reading the mesh, writing only visit stamps), then commit it.
#pragma once

#include <span>
#include <vector>

#include "delaunay/pentatope_store.h"
#include "delaunay/ridge_table.h"

namespace mesh4d::delaunay {

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

  // --- The three steps of an insertion ------------------------------------------------------

  /// A pentatope that contains p in its closure (finite), or an infinite pentatope whose hull
  /// facet sees p strictly from outside. Walks from `hint` (any live pentatope, or kNoCell).
  CellId locate(const Point4& p, CellId hint) const;

  /// Whether the pentatope's (perturbed) circumsphere contains the point p with id pid.
  bool in_conflict(CellId c, const Point4& p, VertexId pid) const;

  /// Fills `cavity` with the conflict region of p (id pid) grown from `start`, which must be in
  /// conflict. Stamps visited pentatopes; changes nothing else.
  void find_cavity(const Point4& p, VertexId pid, CellId start, Cavity& cavity);

  /// Replaces the cavity by the star of vertex pid. Returns one new pentatope.
  CellId commit(const Cavity& cavity, VertexId pid);

  // --- Queries -----------------------------------------------------------------------------

  /// 4 once the first pentatope exists, -1 before.
  int dimension() const { return dimension_; }
  /// Vertices in the triangulation (not the infinite one, pending or removed ones).
  std::size_t number_of_vertices() const { return vertex_count_; }
  std::size_t number_of_cells() const { return store_.live_cells(); }
  std::size_t number_of_finite_cells() const;
  const PentatopeStore& store() const { return store_; }
  /// A live pentatope, or kNoCell while dimension() < 4.
  CellId any_cell() const { return any_cell_; }

  /// The pentatopes incident to vertex v (its star), v in the triangulation.
  void incident_cells(VertexId v, std::vector<CellId>& cells) const { collect_star(v, cells); }

  /// The exact pentatope orientation with point p in slot i (p replacing v[i]).
  int orient_with(CellId c, int i, const Point4& p) const;

 private:
  InsertResult insert_pending(const Point4& p, VertexKind kind);
  void try_build_initial_simplex();
  void build_initial_simplex(VertexId b[5]);
  void insert_vertex_into_mesh(VertexId v, CellId hint, CellId* last);
  void collect_star(VertexId v, std::vector<CellId>& star) const;
  std::uint32_t next_stamp();

  PentatopeStore store_;
  int dimension_ = -1;
  std::size_t vertex_count_ = 0;
  CellId any_cell_ = kNoCell;
  std::vector<VertexId> pending_;  // vertices waiting for the first simplex
  std::uint32_t stamp_ = 0;
  Cavity scratch_cavity_;
  std::vector<CellId> created_;  // pentatopes made by the current commit
  RidgeTable ridges_;
  mutable std::uint64_t walk_rng_ = 0x9e3779b97f4a7c15ull;
};

}  // namespace mesh4d::delaunay
