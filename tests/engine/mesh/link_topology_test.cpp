// The link tests on surfaces whose topology is known: spheres of every size (links of up to 64
// vertices take a table, larger ones a sort: both are checked), and the ways a boundary
// vertex's link fails in a mesh (two spheres at a point or at two points, a torus, a hole, an
// edge in four triangles).
#include "mesh/link_topology.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace mesh4d::mesh {
namespace {

using Triangles = std::vector<std::array<std::uint32_t, 3>>;

std::array<std::uint32_t, 3> sorted(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  std::array<std::uint32_t, 3> t{a, b, c};
  std::sort(t.begin(), t.end());
  return t;
}

// A double cone over a ring of n vertices (first .. first+n-1), apexes first+n and first+n+1:
// a 2-sphere with n + 2 vertices.
Triangles bipyramid(std::uint32_t n, std::uint32_t first = 0) {
  Triangles t;
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t apex : {first + n, first + n + 1})
      t.push_back(sorted(first + i, first + (i + 1) % n, apex));
  return t;
}

// The 7-vertex torus (Möbius–Császár): triangles {i, i+1, i+3} and {i, i+2, i+3} mod 7.
Triangles torus() {
  Triangles t;
  for (std::uint32_t i = 0; i < 7; ++i) {
    t.push_back(sorted(i, (i + 1) % 7, (i + 3) % 7));
    t.push_back(sorted(i, (i + 2) % 7, (i + 3) % 7));
  }
  return t;
}

TEST(LinkTopology, SpheresOfEverySizeAreSpheres) {
  for (std::uint32_t n : {3u, 4u, 10u, 61u, 62u, 63u, 64u, 100u, 1000u})
    EXPECT_TRUE(link_is_sphere(bipyramid(n, 1000))) << n + 2 << " vertices";
}

TEST(LinkTopology, BrokenSpheresAreNot) {
  for (std::uint32_t n : {4u, 40u, 200u}) {
    SCOPED_TRACE(n);
    Triangles holed = bipyramid(n);
    holed.pop_back();
    EXPECT_FALSE(link_is_sphere(holed));
    holed.pop_back();  // an even count again, still with a hole
    EXPECT_FALSE(link_is_sphere(holed));
    // Two spheres sharing one vertex (the second's apex renamed to the first's).
    Triangles two = bipyramid(n);
    for (auto t : bipyramid(n, 2 * n)) {
      for (auto& v : t)
        if (v == 3 * n) v = n;
      std::sort(t.begin(), t.end());
      two.push_back(t);
    }
    EXPECT_FALSE(link_is_sphere(two));
    // Two spheres sharing two vertices, not an edge: χ = 2 but not one sphere.
    Triangles twice = bipyramid(n);
    for (auto t : bipyramid(n, 2 * n)) {
      for (auto& v : t) v = v == 3 * n ? n : v == 3 * n + 1 ? n + 1 : v;
      std::sort(t.begin(), t.end());
      twice.push_back(t);
    }
    EXPECT_FALSE(link_is_sphere(twice));
    // Two spheres sharing an edge: that edge in four triangles.
    Triangles edge = bipyramid(n);
    for (auto t : bipyramid(n, 2 * n)) {
      for (auto& v : t) v = v == 2 * n ? 0 : v == 3 * n ? n : v;
      std::sort(t.begin(), t.end());
      edge.push_back(t);
    }
    EXPECT_FALSE(link_is_sphere(edge));
  }
  EXPECT_FALSE(link_is_sphere(torus()));
  EXPECT_FALSE(link_is_sphere({}));
}

TEST(LinkTopology, CirclesAreOneCycle) {
  std::vector<std::array<std::uint32_t, 2>> ring, two_rings;
  for (std::uint32_t i = 0; i < 5; ++i) ring.push_back({i, (i + 1) % 5});
  for (auto& e : ring) std::sort(e.begin(), e.end());
  EXPECT_TRUE(link_is_circle(ring));
  two_rings = ring;
  for (auto e : ring) two_rings.push_back({e[0] + 10, e[1] + 10});
  EXPECT_FALSE(link_is_circle(two_rings));
  ring.pop_back();
  EXPECT_FALSE(link_is_circle(ring));
}

}  // namespace
}  // namespace mesh4d::mesh
