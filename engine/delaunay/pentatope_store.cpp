#include "delaunay/pentatope_store.h"

#include <limits>
#include <stdexcept>

namespace mesh4d::delaunay {

namespace {
// Slots an allocator takes at once: few enough that the unused rest of a range is no waste,
// many enough that threads rarely meet on the shared counter.
constexpr CellId kRefill = 256;
}  // namespace

PentatopeStore::PentatopeStore(unsigned block_shift)
    : cells_(block_shift),
      vertices_(block_shift > 4 ? block_shift - 4 : block_shift),
      points_(block_shift > 4 ? block_shift - 4 : block_shift),
      owners_(block_shift > 4 ? block_shift - 4 : block_shift) {
  reset();
}

void PentatopeStore::reset() {
  cell_slots_.store(0, std::memory_order_relaxed);
  vertex_slots_.store(0, std::memory_order_relaxed);
  own_ = CellAllocator{};
  // Vertex 0 is the infinite vertex; its point is never read by a predicate.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  add_vertex({nan, nan, nan, nan}, VertexKind::infinite);
}

void PentatopeStore::refill(CellAllocator& a) {
  const std::size_t begin = cell_slots_.fetch_add(kRefill, std::memory_order_relaxed);
  if (begin + kRefill > kNoCell) throw std::length_error("PentatopeStore: out of pentatope ids");
  cells_.ensure(begin + kRefill);
  for (std::size_t c = begin; c < begin + kRefill; ++c) {
    std::atomic_ref(cells_[c].v[0]).store(kNoVertex, std::memory_order_relaxed);
    cells_[c].mark = 0;
  }
  a.next = static_cast<CellId>(begin);
  a.end = static_cast<CellId>(begin + kRefill);
}

void PentatopeStore::merge(CellAllocator& a) {
  // The unused fresh slots are dead already: they only join the free list.
  for (CellId c = a.next; c < a.end; ++c) {
    cells_[c].n[0] = a.free_head;
    a.free_head = c;
  }
  while (a.free_head != kNoCell) {
    const CellId c = a.free_head;
    a.free_head = cells_[c].n[0];
    cells_[c].n[0] = own_.free_head;
    own_.free_head = c;
  }
  own_.live += a.live;
  a = CellAllocator{};
}

VertexId PentatopeStore::add_vertex(const Point4& p, VertexKind kind, std::uint32_t owner) {
  return add_vertices({&p, 1}, kind, owner);
}

VertexId PentatopeStore::add_vertices(std::span<const Point4> points, VertexKind kind,
                                      std::uint32_t owner) {
  const std::size_t first = vertex_slots_.fetch_add(points.size(), std::memory_order_relaxed);
  if (first + points.size() > kNoVertex)
    throw std::length_error("PentatopeStore: out of vertex ids");
  vertices_.ensure(first + points.size());
  points_.ensure(first + points.size());
  owners_.ensure(first + points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    points_[first + k] = points[k];
    vertices_[first + k] = Vertex{kNoCell, kind};
    owners_[first + k] = owner;
  }
  return static_cast<VertexId>(first);
}

void PentatopeStore::prepare_concurrent(std::size_t max_vertices) {
  cells_.reserve_blocks(std::size_t{kNoCell} + 1);
  vertices_.reserve_blocks(max_vertices);
  points_.reserve_blocks(max_vertices);
  owners_.reserve_blocks(max_vertices);
}

}  // namespace mesh4d::delaunay
