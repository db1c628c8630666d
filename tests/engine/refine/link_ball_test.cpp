// grow_link_ball (refine/link_ball.h) against an independent test of what it promises: the
// boundary of what it grows, in the link of an interior vertex of a real triangulation, is a
// 2-sphere (mesh/link_topology.h, which shares no code with it).
#include "refine/link_ball.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "delaunay/triangulation.h"
#include "mesh/link_topology.h"

namespace mesh4d::refine {
namespace {

using delaunay::CellId;

struct Star {
  delaunay::Triangulation tri;
  mesh4d::VertexId center = 0;
  std::vector<CellId> cells;
};

// Random points in a box and one at its middle, whose star is then far from the hull.
void build(Star& s, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 10);
  for (int i = 0; i < 400; ++i) s.tri.insert({u(rng), u(rng), u(rng), u(rng)});
  s.center = s.tri.insert({5.01, 4.99, 5.02, 4.98}).vertex;
  s.tri.incident_cells(s.center, s.cells);
}

// The triangles of the link bounding `in` (sorted vertex triples), as the certificate sees them.
std::vector<std::array<std::uint32_t, 3>> boundary_in_link(const Star& s,
                                                           const std::vector<char>& in) {
  const auto& st = s.tri.store();
  std::vector<std::array<std::uint32_t, 3>> faces;
  for (std::size_t k = 0; k < s.cells.size(); ++k) {
    if (!in[k]) continue;
    const auto& cell = st.cell(s.cells[k]);
    for (int q = 0; q < 5; ++q) {
      if (cell.v[q] == s.center) continue;
      const auto it = std::find(s.cells.begin(), s.cells.end(), cell.n[q]);
      if (it != s.cells.end() && in[it - s.cells.begin()]) continue;
      std::array<std::uint32_t, 3> t;
      for (int i = 0, n = 0; i < 5; ++i)
        if (i != q && cell.v[i] != s.center) t[n++] = cell.v[i];
      std::sort(t.begin(), t.end());
      faces.push_back(t);
    }
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

TEST(LinkBall, WhatItGrowsIsBoundedByASphereAndStaysWhereAllowed) {
  std::mt19937 rng(7);
  Star s;
  build(s, rng);
  ASSERT_GT(s.cells.size(), 40u);
  for (CellId c : s.cells)
    for (auto v : s.tri.store().cell(c).v) ASSERT_NE(v, delaunay::kInfiniteVertex);
  std::bernoulli_distribution keep(0.85);
  std::size_t grown_past_seed = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<char> allowed(s.cells.size());
    for (auto& a : allowed) a = keep(rng);
    const std::size_t seed = rng() % s.cells.size();
    allowed[seed] = 1;
    const std::vector<char> ball = grow_link_ball(s.tri.store(), s.center, s.cells, allowed, seed);
    ASSERT_TRUE(ball[seed]);
    std::size_t size = 0;
    for (std::size_t k = 0; k < ball.size(); ++k) {
      EXPECT_TRUE(!ball[k] || allowed[k]) << k;
      size += ball[k];
    }
    grown_past_seed += size > 1;
    EXPECT_TRUE(mesh::link_is_sphere(boundary_in_link(s, ball))) << "trial " << trial;
  }
  EXPECT_GT(grown_past_seed, 150u);
}

// With every pentatope allowed the ball takes all but the last one, which would close it.
TEST(LinkBall, GrowsThroughTheWholeSphereButOne) {
  std::mt19937 rng(11);
  Star s;
  build(s, rng);
  const std::vector<char> all(s.cells.size(), 1);
  const std::vector<char> ball = grow_link_ball(s.tri.store(), s.center, s.cells, all, 0);
  EXPECT_EQ(static_cast<std::size_t>(std::count(ball.begin(), ball.end(), 1)), s.cells.size() - 1);
  EXPECT_TRUE(mesh::link_is_sphere(boundary_in_link(s, ball)));
}

}  // namespace
}  // namespace mesh4d::refine
