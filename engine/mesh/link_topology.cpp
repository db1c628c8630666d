#include "mesh/link_topology.h"

#include <algorithm>
#include <utility>

#include "support/union_find.h"

namespace mesh4d::mesh {

using Id = std::uint32_t;
using support::UnionFind;

namespace {

// The sphere test for a link of at most kSmall vertices (nearly every one: a vertex of a 4D
// Delaunay mesh has some 10 to 40 neighbors on its region's boundary): vertices renamed
// 0..V-1, each edge counted in a V×V table with one of its triangles. No sort, no allocation.
constexpr std::size_t kSmall = 64;

// The local names of the link's vertices; false when there are more than kSmall.
bool rename(const std::vector<std::array<Id, 3>>& triangles, std::array<std::uint8_t, 3>* local,
            std::size_t* count) {
  std::array<Id, kSmall> names;
  std::size_t v = 0;
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Id x = triangles[t][k];
      std::size_t i = 0;
      while (i < v && names[i] != x) ++i;
      if (i == v) {
        if (v == kSmall) return false;
        names[v++] = x;
      }
      local[t][k] = static_cast<std::uint8_t>(i);
    }
  *count = v;
  return true;
}

bool small_link_is_sphere(const std::vector<std::array<Id, 3>>& triangles) {
  // At most 2·(kSmall − 2) triangles reach here (the caller's count check).
  std::array<std::array<std::uint8_t, 3>, 2 * kSmall> local;
  std::size_t v = 0;
  if (!rename(triangles, local.data(), &v)) return false;     // more vertices than a sphere's
  std::array<std::array<std::uint8_t, kSmall>, kSmall> uses;  // per edge (a < b)
  std::array<std::array<std::uint8_t, kSmall>, kSmall> first;
  for (std::size_t a = 0; a < v; ++a) std::fill_n(uses[a].begin(), v, 0);
  std::array<std::uint8_t, 2 * kSmall> parent{};  // union-find over the triangles
  for (std::size_t t = 0; t < triangles.size(); ++t) parent[t] = static_cast<std::uint8_t>(t);
  const auto find = [&](std::uint8_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::size_t e = 0, open = 0;  // edges, and those seen once so far
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      std::uint8_t a = local[t][k], b = local[t][(k + 1) % 3];
      if (a > b) std::swap(a, b);
      switch (uses[a][b]++) {
        case 0:
          first[a][b] = static_cast<std::uint8_t>(t);
          ++e, ++open;
          break;
        case 1:
          parent[find(first[a][b])] = find(static_cast<std::uint8_t>(t));
          --open;
          break;
        default:
          return false;
      }
    }
  if (open) return false;
  const std::uint8_t root = find(0);
  for (std::size_t t = 1; t < triangles.size(); ++t)
    if (find(static_cast<std::uint8_t>(t)) != root) return false;
  return static_cast<long>(v) - static_cast<long>(e) + static_cast<long>(triangles.size()) == 2;
}

}  // namespace

// Whether the triangles around a boundary vertex form a 2-sphere: each of their edges in exactly
// two of them, connected through shared edges, and Euler characteristic 2.
bool link_is_sphere(const std::vector<std::array<Id, 3>>& triangles) {
  // A 2-sphere of T triangles has 2 + T/2 vertices.
  if (triangles.size() < 4 || triangles.size() % 2 || triangles.size() > 65535) return false;
  if (2 + triangles.size() / 2 <= kSmall) return small_link_is_sphere(triangles);
  // A closed surface has every edge twice; the edges as 64-bit keys, each with its triangle,
  // sorted.
  struct Edge {
    std::uint64_t key;
    std::uint32_t triangle;
  };
  thread_local std::vector<Edge> edges;
  thread_local std::vector<Id> vertices;
  edges.clear();
  vertices.clear();
  const auto key = [](Id a, Id b) { return std::uint64_t{a} << 32 | b; };
  for (std::uint32_t t = 0; t < triangles.size(); ++t) {
    const auto& [a, b, c] = triangles[t];
    edges.push_back({key(a, b), t});
    edges.push_back({key(a, c), t});
    edges.push_back({key(b, c), t});
    vertices.insert(vertices.end(), {a, b, c});
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.key < y.key; });
  UnionFind pieces(triangles.size());
  std::size_t e = 0;
  for (std::size_t i = 0; i < edges.size(); i += 2, ++e) {
    if (i + 1 >= edges.size() || edges[i + 1].key != edges[i].key ||
        (i + 2 < edges.size() && edges[i + 2].key == edges[i].key))
      return false;
    pieces.join(edges[i].triangle, edges[i + 1].triangle);
  }
  for (std::size_t t = 1; t < triangles.size(); ++t)
    if (pieces.find(t) != pieces.find(0)) return false;
  std::sort(vertices.begin(), vertices.end());
  const std::size_t v = std::unique(vertices.begin(), vertices.end()) - vertices.begin();
  return static_cast<long>(v) - static_cast<long>(e) + static_cast<long>(triangles.size()) == 2;
}

// Whether the edges around a boundary edge form one circle: every vertex in exactly two of them,
// and connected.
bool link_is_circle(const std::vector<std::array<Id, 2>>& edges) {
  std::vector<Id> ends;
  for (const auto& [a, b] : edges) ends.insert(ends.end(), {a, b});
  std::sort(ends.begin(), ends.end());
  for (std::size_t i = 0; i < ends.size(); i += 2)
    if (i + 1 >= ends.size() || ends[i] != ends[i + 1] ||
        (i + 2 < ends.size() && ends[i + 2] == ends[i]))
      return false;
  std::vector<Id> vertices(ends.begin(), ends.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  const auto index = [&](Id x) {
    return static_cast<std::size_t>(std::lower_bound(vertices.begin(), vertices.end(), x) -
                                    vertices.begin());
  };
  UnionFind pieces(vertices.size());
  for (const auto& [a, b] : edges) pieces.join(index(a), index(b));
  for (std::size_t i = 1; i < vertices.size(); ++i)
    if (pieces.find(i) != pieces.find(0)) return false;
  return true;
}

}  // namespace mesh4d::mesh
