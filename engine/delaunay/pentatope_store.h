// Combinatorics of a 4D triangulation: pentatopes (5 vertex ids, 5 neighbor ids) and vertices
// (point, kind, one incident pentatope), stored flat by index with a free list. No geometry here.
//
// Conventions:
//   - neighbor n[i] is the pentatope across the facet opposite vertex v[i];
//   - vertex 0 is the infinite vertex: pentatopes that contain it close the convex hull;
//   - a dead pentatope has v[0] == kNoVertex and chains the free list through n[0].
#pragma once

#include <cstdint>

#include "delaunay/chunked_array.h"
#include "delaunay/point4.h"

namespace mesh4d::delaunay {

using CellId = std::uint32_t;

inline constexpr VertexId kInfiniteVertex = 0;
inline constexpr VertexId kNoVertex = 0xFFFFFFFFu;
inline constexpr CellId kNoCell = 0xFFFFFFFFu;

/// What a vertex is to the refiner: box corners and box-face points, feature points on ∂Ω
/// (never deleted), free points (may be deleted by R5). `removed` marks a deleted vertex, whose id
/// is never reused (ids order vertices by age for the symbolic tie-break).
enum class VertexKind : std::uint8_t { infinite, box, feature, free, removed };

struct Pentatope {
  VertexId v[5];
  CellId n[5];
  std::uint32_t mark;  // stamp of the last cavity search that visited this pentatope
};
static_assert(sizeof(Pentatope) == 44, "pentatopes are 44 bytes: 10 ids and one stamp");

/// A vertex's combinatorial data; its point is stored apart (PentatopeStore::point), so that the
/// predicates' loads find points packed two to a cache line.
struct Vertex {
  CellId cell;  // one incident pentatope; kNoCell until the vertex is in the triangulation
  VertexKind kind;
};

class PentatopeStore {
 public:
  explicit PentatopeStore(unsigned block_shift = 16);
  /// Back to the state after construction, keeping the storage blocks.
  void reset();

  Pentatope& cell(CellId c) { return cells_[c]; }
  const Pentatope& cell(CellId c) const { return cells_[c]; }
  Vertex& vertex(VertexId v) { return vertices_[v]; }
  const Vertex& vertex(VertexId v) const { return vertices_[v]; }
  const Point4& point(VertexId v) const { return points_[v]; }

  /// A pentatope with the given vertices, neighbors unset (kNoCell) and mark 0.
  CellId create_cell(const VertexId v[5]) {
    const Pentatope cell{
        {v[0], v[1], v[2], v[3], v[4]}, {kNoCell, kNoCell, kNoCell, kNoCell, kNoCell}, 0};
    ++live_cells_;
    if (free_head_ != kNoCell) {
      const CellId c = free_head_;
      free_head_ = cells_[c].n[0];
      cells_[c] = cell;
      return c;
    }
    return static_cast<CellId>(cells_.push_back(cell));
  }
  void destroy_cell(CellId c) {
    Pentatope& cell = cells_[c];
    cell.v[0] = kNoVertex;
    cell.n[0] = free_head_;
    cell.mark = 0;
    free_head_ = c;
    --live_cells_;
  }

  VertexId add_vertex(const Point4& p, VertexKind kind);

  bool is_live(CellId c) const { return c < cells_.size() && cells_[c].v[0] != kNoVertex; }
  bool is_infinite(CellId c) const { return index_of(c, kInfiniteVertex) >= 0; }
  /// Slot of vertex v in pentatope c, or -1.
  int index_of(CellId c, VertexId v) const {
    const Pentatope& cell = cells_[c];
    for (int i = 0; i < 5; ++i)
      if (cell.v[i] == v) return i;
    return -1;
  }
  /// Slot i with c.n[i] == neighbor, or -1.
  int neighbor_index(CellId c, CellId neighbor) const {
    const Pentatope& cell = cells_[c];
    for (int i = 0; i < 5; ++i)
      if (cell.n[i] == neighbor) return i;
    return -1;
  }

  std::size_t cell_slots() const { return cells_.size(); }  // live + free
  std::size_t live_cells() const { return live_cells_; }
  std::size_t vertex_slots() const { return vertices_.size(); }  // includes the infinite vertex
  std::size_t memory_bytes() const {
    return cells_.capacity_bytes() + vertices_.capacity_bytes() + points_.capacity_bytes();
  }

 private:
  ChunkedArray<Pentatope> cells_;
  ChunkedArray<Vertex> vertices_;
  ChunkedArray<Point4> points_;
  CellId free_head_ = kNoCell;
  std::size_t live_cells_ = 0;
};

}  // namespace mesh4d::delaunay
