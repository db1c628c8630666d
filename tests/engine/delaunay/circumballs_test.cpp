#include "delaunay/circumballs.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "delaunay/geometry.h"

namespace mesh4d::delaunay {
namespace {

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Measures `simplices` four at a time (both code paths) and one at a time: the same bits.
void expect_same_as_scalar(const std::vector<Simplex4>& simplices) {
  ASSERT_EQ(simplices.size() % 4, 0u);
  for (std::size_t i = 0; i < simplices.size(); i += 4) {
    const Point4* vertices[4][5];
    for (int l = 0; l < 4; ++l)
      for (int k = 0; k < 5; ++k) vertices[l][k] = &simplices[i + l][k];
    for (bool portable : {false, true}) {
      Circumball balls[4];
      circumballs4(vertices, balls, portable);
      for (int l = 0; l < 4; ++l) {
        const Simplex4& s = simplices[i + l];
        const Point4 center = circumcenter(s);
        for (int j = 0; j < 4; ++j)
          EXPECT_TRUE(same_bits(balls[l].center[j], center[j]))
              << "simplex " << i + l << " coordinate " << j << (portable ? " (portable)" : "");
        EXPECT_TRUE(same_bits(balls[l].radius, circumradius(s, center))) << "simplex " << i + l;
        EXPECT_TRUE(same_bits(balls[l].shortest_edge, shortest_edge(s))) << "simplex " << i + l;
      }
    }
  }
}

// Five points uniform in [offset, offset + size)⁴.
Simplex4 random_simplex(std::mt19937_64& rng, double offset, double size) {
  std::uniform_real_distribution<double> coordinate(offset, offset + size);
  Simplex4 s;
  for (auto& p : s)
    for (double& x : p) x = coordinate(rng);
  return s;
}

TEST(Circumballs, SameBitsAsOneAtATime) {
  std::mt19937_64 rng(7);
  std::vector<Simplex4> simplices;
  for (int i = 0; i < 400; ++i)
    simplices.push_back(random_simplex(rng, i % 2 ? 1e4 : 0, 10));  // far from the origin too
  expect_same_as_scalar(simplices);
}

TEST(Circumballs, FlatAndNearlyFlatLanesAsOneAtATime) {
  std::mt19937_64 rng(11);
  std::vector<Simplex4> simplices;
  for (int i = 0; i < 200; ++i) {
    Simplex4 s = random_simplex(rng, 0, 1);
    if (i % 4 == 0) s[4] = s[0];                                  // a repeated vertex
    if (i % 4 == 1) s[4] = {s[1][0], s[1][1], s[1][2], s[2][3]};  // mixed coordinates
    if (i % 4 == 2)                                               // five points in t = 0
      for (auto& p : s) p[3] = 0;
    if (i % 4 == 3) s[4][3] = s[3][3] + 1e-13;  // a sliver
    simplices.push_back(s);
  }
  // Grid points: co-spherical and co-planar sets, where exact zeros decide.
  for (int i = 0; i < 40; ++i) {
    Simplex4 s;
    for (auto& p : s)
      for (double& x : p) x = static_cast<double>(rng() % 3);
    simplices.push_back(s);
  }
  expect_same_as_scalar(simplices);
}

}  // namespace
}  // namespace mesh4d::delaunay
