#include "delaunay/pentatope_store.h"

#include <limits>

namespace mesh4d::delaunay {

PentatopeStore::PentatopeStore(unsigned block_shift)
    : cells_(block_shift),
      vertices_(block_shift > 4 ? block_shift - 4 : block_shift),
      points_(block_shift > 4 ? block_shift - 4 : block_shift) {
  reset();
}

void PentatopeStore::reset() {
  cells_.reset();
  vertices_.reset();
  points_.reset();
  free_head_ = kNoCell;
  live_cells_ = 0;
  // Vertex 0 is the infinite vertex; its point is never read by a predicate.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  vertices_.push_back(Vertex{kNoCell, VertexKind::infinite});
  points_.push_back({nan, nan, nan, nan});
}

VertexId PentatopeStore::add_vertex(const Point4& p, VertexKind kind) {
  points_.push_back(p);
  return static_cast<VertexId>(vertices_.push_back(Vertex{kNoCell, kind}));
}

}  // namespace mesh4d::delaunay
