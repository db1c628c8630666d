// Combinatorics of a 4D triangulation: pentatopes (5 vertex ids, 5 neighbor ids) and vertices
// (point, kind, one incident pentatope, a lock word), stored flat by index with free lists. No
// geometry here.
//
// Conventions:
//   - neighbor n[i] is the pentatope across the facet opposite vertex v[i];
//   - vertex 0 is the infinite vertex: pentatopes that contain it close the convex hull;
//   - a dead pentatope has v[0] == kNoVertex and chains the free list through n[0].
#pragma once

#include <atomic>
#include <cstdint>
#include <span>

#include "delaunay/point4.h"
#include "support/chunked_array.h"

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

/// Where one thread takes pentatope slots from and returns them to: its own free list and a
/// range of fresh slots, so that threads creating and destroying pentatopes at once never share
/// a list. The store has one for single-threaded use; each worker of the parallel refiner has
/// its own, merged back into the store's when the workers stop.
struct CellAllocator {
  CellId free_head = kNoCell;
  CellId next = 0, end = 0;  // fresh slots [next, end), already marked dead
  std::int64_t live = 0;     // pentatopes created minus destroyed through this allocator
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
  CellId create_cell(const VertexId v[5]) { return create_cell(v, own_); }
  void destroy_cell(CellId c) { destroy_cell(c, own_); }

  // Pentatope vertex ids are written with atomic stores (plain moves on x86) so that a thread
  // may check whether a slot still holds the pentatope it queued (still_holds) while another
  // thread reuses the slot; every other access happens under the vertex locks.
  CellId create_cell(const VertexId v[5], CellAllocator& a) {
    CellId c;
    if (a.free_head != kNoCell) {
      c = a.free_head;
      a.free_head = cells_[c].n[0];
    } else {
      if (a.next == a.end) refill(a);
      c = a.next++;
    }
    Pentatope& cell = cells_[c];
    for (int i = 0; i < 5; ++i) {
      std::atomic_ref(cell.v[i]).store(v[i], std::memory_order_relaxed);
      cell.n[i] = kNoCell;
    }
    cell.mark = 0;
    ++a.live;
    return c;
  }
  void destroy_cell(CellId c, CellAllocator& a) {
    Pentatope& cell = cells_[c];
    std::atomic_ref(cell.v[0]).store(kNoVertex, std::memory_order_relaxed);
    cell.n[0] = a.free_head;
    cell.mark = 0;
    a.free_head = c;
    --a.live;
  }
  /// The allocator of single-threaded use.
  CellAllocator& own_allocator() { return own_; }
  /// Gives a worker's free slots and count back to the store's own allocator.
  void merge(CellAllocator& a);

  /// Whether slot c holds a live pentatope with exactly these vertices. Safe while other
  /// threads create and destroy pentatopes.
  bool still_holds(CellId c, const VertexId v[5]) const {
    if (c >= cell_slots()) return false;
    const Pentatope& cell = cells_[c];
    for (int i = 0; i < 5; ++i)
      if (std::atomic_ref(const_cast<VertexId&>(cell.v[i])).load(std::memory_order_relaxed) != v[i])
        return false;
    return true;
  }

  /// A new vertex (thread-safe: ids come from an atomic counter, so they still order vertices
  /// by age). `owner` is its lock word's first value (0: unlocked).
  VertexId add_vertex(const Point4& p, VertexKind kind, std::uint32_t owner = 0);
  /// New vertices with consecutive ids, the first returned (thread-safe too): their ids order
  /// them against every other vertex alike.
  VertexId add_vertices(std::span<const Point4> points, VertexKind kind, std::uint32_t owner = 0);
  /// The lock word of vertex v (VertexLocks): 0, or the id of the thread that holds it.
  std::uint32_t& owner(VertexId v) { return owners_[v]; }

  bool is_live(CellId c) const { return c < cell_slots() && cells_[c].v[0] != kNoVertex; }
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
    // Without branches: which slot matches is as good as random (a mispredicted branch in
    // every new pentatope's linking).
    const Pentatope& cell = cells_[c];
    int slot = -1;
    for (int i = 4; i >= 0; --i) slot = cell.n[i] == neighbor ? i : slot;
    return slot;
  }

  /// Slots handed out (live, free, or reserved by an allocator), all initialised.
  std::size_t cell_slots() const { return cell_slots_.load(std::memory_order_relaxed); }
  /// Live pentatopes, counting only what went through the store's own allocator or was merged.
  std::size_t live_cells() const { return static_cast<std::size_t>(own_.live); }
  /// Vertex ids handed out, including the infinite vertex and removed ones.
  std::size_t vertex_slots() const { return vertex_slots_.load(std::memory_order_relaxed); }
  std::size_t memory_bytes() const {
    return cells_.capacity_bytes() + vertices_.capacity_bytes() + points_.capacity_bytes() +
           owners_.capacity_bytes();
  }
  /// Prepares for threads that create pentatopes and vertices at once: block tables that never
  /// move, for every cell id and for up to `max_vertices` vertex ids.
  void prepare_concurrent(std::size_t max_vertices);

 private:
  void refill(CellAllocator& a);  // a fresh range of dead slots

  support::ChunkedArray<Pentatope> cells_;
  support::ChunkedArray<Vertex> vertices_;
  support::ChunkedArray<Point4> points_;
  support::ChunkedArray<std::uint32_t> owners_;
  std::atomic<std::size_t> cell_slots_{0};
  std::atomic<std::size_t> vertex_slots_{0};
  CellAllocator own_;
};

}  // namespace mesh4d::delaunay
