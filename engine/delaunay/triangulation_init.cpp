// The start of a triangulation: vertices wait until five of them are affinely independent, then
// the first pentatope and its five infinite neighbors are built and the waiting vertices inserted.
#include <CGAL/Gmpq.h>

#include <algorithm>
#include <vector>

#include "delaunay/predicates.h"
#include "delaunay/triangulation.h"

namespace mesh4d::delaunay {
namespace {

// Exact affine rank of a few points (rational elimination; runs only before the first simplex).
int affine_rank(const std::vector<const Point4*>& pts) {
  if (pts.empty()) return -1;
  std::vector<std::vector<CGAL::Gmpq>> m;
  for (std::size_t i = 1; i < pts.size(); ++i) {
    std::vector<CGAL::Gmpq> row(4);
    for (int j = 0; j < 4; ++j) row[j] = CGAL::Gmpq((*pts[i])[j]) - CGAL::Gmpq((*pts[0])[j]);
    m.push_back(row);
  }
  int rank = 0;
  for (int col = 0; col < 4 && rank < static_cast<int>(m.size()); ++col) {
    std::size_t pivot = rank;
    while (pivot < m.size() && m[pivot][col] == 0) ++pivot;
    if (pivot == m.size()) continue;
    std::swap(m[pivot], m[rank]);
    for (std::size_t r = rank + 1; r < m.size(); ++r) {
      const CGAL::Gmpq f = m[r][col] / m[rank][col];
      for (int c = col; c < 4; ++c) m[r][c] -= f * m[rank][c];
    }
    ++rank;
  }
  return rank;
}

}  // namespace

Triangulation::InsertResult Triangulation::insert_pending(const Point4& p, VertexKind kind) {
  for (VertexId u : pending_)
    if (store_.point(u) == p) return {u, false, kNoCell};
  const VertexId v = new_vertex(p, kind, 0);
  pending_.push_back(v);
  try_build_initial_simplex();
  return {v, true, dimension_ == 4 ? store_.vertex(v).cell : kNoCell};
}

void Triangulation::try_build_initial_simplex() {
  // Greedy basis: keep a vertex when it raises the affine rank.
  std::vector<VertexId> basis;
  std::vector<const Point4*> pts;
  for (VertexId u : pending_) {
    pts.push_back(&store_.point(u));
    if (affine_rank(pts) == static_cast<int>(pts.size()) - 1) {
      basis.push_back(u);
      if (basis.size() == 5) break;
    } else {
      pts.pop_back();
    }
  }
  if (basis.size() < 5) return;

  VertexId b[5] = {basis[0], basis[1], basis[2], basis[3], basis[4]};
  build_initial_simplex(b);
  // The other waiting vertices go in by the ordinary insertion, oldest first.
  std::vector<VertexId> rest;
  for (VertexId u : pending_)
    if (std::find(basis.begin(), basis.end(), u) == basis.end()) rest.push_back(u);
  pending_.clear();
  CellId hint = any_cell();
  for (VertexId u : rest) insert_vertex_into_mesh(u, hint, &hint);
}

void Triangulation::build_initial_simplex(VertexId b[5]) {
  const auto& P = [&](int i) -> const Point4& { return store_.point(b[i]); };
  if (orient4(P(0), P(1), P(2), P(3), P(4)) < 0) std::swap(b[0], b[1]);

  std::vector<CellId> cells;
  cells.push_back(store_.create_cell(b));
  for (int i = 0; i < 5; ++i) {
    VertexId v[5] = {b[0], b[1], b[2], b[3], b[4]};
    v[i] = kInfiniteVertex;
    // Replacing b[i] by the infinite vertex keeps b[i] (inside the hull) in that slot's
    // orientation sign; swapping two finite vertices makes points beyond the facet positive.
    const int j = (i + 1) % 5, k = (i + 2) % 5;
    std::swap(v[j], v[k]);
    cells.push_back(store_.create_cell(v));
  }
  // Neighbors: two of these six pentatopes are adjacent when they share four vertices.
  for (CellId c : cells) {
    for (CellId d : cells) {
      if (c == d) continue;
      int shared = 0, missing = -1;
      for (int i = 0; i < 5; ++i) {
        if (store_.index_of(d, store_.cell(c).v[i]) >= 0)
          ++shared;
        else
          missing = i;
      }
      if (shared == 4) store_.cell(c).n[missing] = d;
    }
  }
  for (CellId c : cells)
    for (VertexId u : store_.cell(c).v) store_.vertex(u).cell = c;
  dimension_ = 4;
  any_cell_ = cells.front();
}

}  // namespace mesh4d::delaunay
