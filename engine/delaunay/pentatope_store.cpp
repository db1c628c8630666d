#include "delaunay/pentatope_store.h"

#include <limits>

namespace mesh4d::delaunay {

PentatopeStore::PentatopeStore(unsigned block_shift)
    : cells_(block_shift), vertices_(block_shift > 4 ? block_shift - 4 : block_shift) {
  // Vertex 0 is the infinite vertex; its point is never read by a predicate.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  vertices_.push_back(Vertex{{nan, nan, nan, nan}, kNoCell, VertexKind::infinite});
}

CellId PentatopeStore::create_cell(const VertexId v[5]) {
  Pentatope cell{{v[0], v[1], v[2], v[3], v[4]}, {kNoCell, kNoCell, kNoCell, kNoCell, kNoCell}, 0};
  ++live_cells_;
  if (free_head_ != kNoCell) {
    const CellId c = free_head_;
    free_head_ = cells_[c].n[0];
    cells_[c] = cell;
    return c;
  }
  return static_cast<CellId>(cells_.push_back(cell));
}

void PentatopeStore::destroy_cell(CellId c) {
  Pentatope& cell = cells_[c];
  cell.v[0] = kNoVertex;
  cell.n[0] = free_head_;
  cell.mark = 0;
  free_head_ = c;
  --live_cells_;
}

VertexId PentatopeStore::add_vertex(const Point4& p, VertexKind kind) {
  return static_cast<VertexId>(vertices_.push_back(Vertex{p, kNoCell, kind}));
}

bool PentatopeStore::is_infinite(CellId c) const {
  const Pentatope& cell = cells_[c];
  return cell.v[0] == kInfiniteVertex || cell.v[1] == kInfiniteVertex ||
         cell.v[2] == kInfiniteVertex || cell.v[3] == kInfiniteVertex ||
         cell.v[4] == kInfiniteVertex;
}

int PentatopeStore::index_of(CellId c, VertexId v) const {
  const Pentatope& cell = cells_[c];
  for (int i = 0; i < 5; ++i)
    if (cell.v[i] == v) return i;
  return -1;
}

int PentatopeStore::neighbor_index(CellId c, CellId neighbor) const {
  const Pentatope& cell = cells_[c];
  for (int i = 0; i < 5; ++i)
    if (cell.n[i] == neighbor) return i;
  return -1;
}

}  // namespace mesh4d::delaunay
