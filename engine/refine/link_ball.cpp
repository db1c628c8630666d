#include "refine/link_ball.h"

#include <algorithm>
#include <array>
#include <deque>
#include <utility>

namespace mesh4d::refine {

using delaunay::CellId;

namespace {

// One pentatope of the star seen as a tetrahedron of v's link: its four other vertices (as
// places in the link's vertex list) and, across the face opposite each, the neighbor's place in
// the star (-1 when outside it, which an interior vertex's star never has).
struct LinkTet {
  std::array<int, 4> w;
  std::array<int, 4> across;
};

}  // namespace

std::vector<char> grow_link_ball(const delaunay::PentatopeStore& store, mesh4d::VertexId v,
                                 std::span<const CellId> star, const std::vector<char>& allowed,
                                 std::size_t seed) {
  const std::size_t n = star.size();
  std::vector<mesh4d::VertexId> vertices;
  for (CellId c : star)
    for (mesh4d::VertexId u : store.cell(c).v)
      if (u != v) vertices.push_back(u);
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  const auto place = [&](mesh4d::VertexId u) {
    return static_cast<int>(std::lower_bound(vertices.begin(), vertices.end(), u) -
                            vertices.begin());
  };
  std::vector<std::pair<CellId, int>> index(n);
  for (std::size_t k = 0; k < n; ++k) index[k] = {star[k], static_cast<int>(k)};
  std::sort(index.begin(), index.end());
  std::vector<LinkTet> tets(n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto& cell = store.cell(star[k]);
    for (int q = 0, i = 0; q < 5; ++q) {
      if (cell.v[q] == v) continue;
      tets[k].w[i] = place(cell.v[q]);
      const auto it = std::lower_bound(index.begin(), index.end(), std::pair{cell.n[q], -1});
      tets[k].across[i] = it != index.end() && it->first == cell.n[q] ? it->second : -1;
      ++i;
    }
  }

  // The ball's closure: how many of its tetrahedra hold each link vertex and edge.
  const std::size_t m = vertices.size();
  std::vector<int> vertex_uses(m, 0), edge_uses(m * m, 0);
  std::vector<char> in(n, 0);
  const auto add = [&](std::size_t k) {
    in[k] = 1;
    const auto& w = tets[k].w;
    for (int i = 0; i < 4; ++i) {
      ++vertex_uses[w[i]];
      for (int j = i + 1; j < 4; ++j) ++edge_uses[w[i] * m + w[j]], ++edge_uses[w[j] * m + w[i]];
    }
  };
  // A tetrahedron joins a ball into a ball exactly when they meet in a disk: one to three of its
  // faces, and nothing else (faces are shared only through the neighbor across them).
  // A tetrahedron joins a ball into a ball exactly when they meet in a disk: one to three of its
  // faces, and nothing else (a face is the ball's only through the neighbor across it). One
  // face: the vertex opposite it lies off the ball. Two: the edge joining the vertices opposite
  // them (the only simplex the two faces miss) does. Three: the faces hold every vertex and edge.
  const auto meets_in_disk = [&](std::size_t k) {
    std::array<int, 4> opposite{};  // its vertices opposite the faces it shares with the ball
    int shared = 0;
    for (int i = 0; i < 4; ++i) {
      const int j = tets[k].across[i];
      if (j >= 0 && in[j]) opposite[shared++] = tets[k].w[i];
    }
    if (shared == 1) return vertex_uses[opposite[0]] == 0;
    if (shared == 2) return edge_uses[opposite[0] * m + opposite[1]] == 0;
    return shared == 3;
  };

  if (!allowed[seed]) return in;
  add(seed);
  std::deque<std::size_t> queue;
  std::vector<std::size_t> waiting;
  const auto offer_neighbors = [&](std::size_t k) {
    for (int j : tets[k].across)
      if (j >= 0 && !in[j] && allowed[j]) queue.push_back(static_cast<std::size_t>(j));
  };
  offer_neighbors(seed);
  // Breadth first, so the ball grows round from the seed; one refused now may fit once the
  // ball has grown around it, so the refused are offered again while the ball still grows.
  for (bool grew = true; grew;) {
    grew = false;
    while (!queue.empty()) {
      const std::size_t k = queue.front();
      queue.pop_front();
      if (in[k]) continue;
      if (!meets_in_disk(k)) {
        waiting.push_back(k);
        continue;
      }
      add(k);
      grew = true;
      offer_neighbors(k);
    }
    queue.assign(waiting.begin(), waiting.end());
    waiting.clear();
  }
  return in;
}

}  // namespace mesh4d::refine
