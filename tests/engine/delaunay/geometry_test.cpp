#include "delaunay/geometry.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mesh4d::delaunay {
namespace {

// The regular pentatope: the five unit vectors of R⁵ projected onto the hyperplane Σx = 1, in an
// orthonormal basis of that hyperplane. Built here from the 4-simplex with edge √2.
Simplex4 regular_pentatope() {
  const double a = (1 - std::sqrt(5.0)) / 4;  // fifth vertex (a, a, a, a): all edges √2
  return {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}, {a, a, a, a}}};
}

TEST(Geometry, RegularPentatopeHasUnitNormalizedVolume) {
  const Simplex4 s = regular_pentatope();
  EXPECT_NEAR(shortest_edge(s), std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(radius_edge_ratio(s), std::sqrt(0.4), 1e-12);
  EXPECT_NEAR(normalized_volume(s), 1.0, 1e-12);
}

TEST(Geometry, CircumcenterIsEquidistant) {
  const Simplex4 s{{{0.1, 0.2, 0.3, 0.4},
                    {1.3, 0.1, 0.2, 0.5},
                    {0.2, 1.1, 0.3, 0.1},
                    {0.4, 0.3, 1.7, 0.2},
                    {0.3, 0.2, 0.1, 0.9}}};
  const Point4 c = circumcenter(s);
  const double r = circumradius(s);
  for (const Point4& p : s) {
    double d2 = 0;
    for (int j = 0; j < 4; ++j) d2 += (p[j] - c[j]) * (p[j] - c[j]);
    EXPECT_NEAR(std::sqrt(d2), r, 1e-12);
  }
}

TEST(Geometry, UnitSimplexVolumeAndFarFromOrigin) {
  Simplex4 s{{{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
  EXPECT_NEAR(signed_volume(s), 1.0 / 24, 1e-15);
  const Point4 c = circumcenter(s);
  for (double x : c) EXPECT_NEAR(x, 0.5, 1e-15);
  // The same simplex translated far away keeps its measures (computed relative to a vertex).
  for (auto& p : s)
    for (double& x : p) x += 1e6;
  EXPECT_NEAR(radius_edge_ratio(s), 1.0, 1e-9);
  const Point4 c2 = circumcenter(s);
  for (double x : c2) EXPECT_NEAR(x, 1e6 + 0.5, 1e-6);
}

TEST(Geometry, FlatSimplexHasZeroNormalizedVolumeAndInfiniteRadius) {
  const Simplex4 s{{{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {1, 1, 1, 0}}};
  EXPECT_TRUE(std::isinf(circumradius(s)));
  EXPECT_EQ(normalized_volume(s), 0.0);
  EXPECT_EQ(signed_volume(s), 0.0);
}

TEST(Geometry, FacetNormalGivesTheOrientationDeterminant) {
  const Tetrahedron4 f{{{0.1, 0.2, 0.3, 0.4}, {1.3, 0.1, 0.2, 0.5}, {0.2, 1.1, 0.3, 0.1},
                        {0.4, 0.3, 1.7, 0.2}}};
  const Point4 u{0.3, 0.2, 0.1, 0.9};
  const Point4 n = hyperplane_normal(f);
  // n · (u − f₀) = det[f₁−f₀; f₂−f₀; f₃−f₀; u−f₀] = 24 · the signed volume of (f, u).
  double height = 0;
  for (int k = 0; k < 4; ++k) height += n[k] * (u[k] - f[0][k]);
  EXPECT_NEAR(height, 24 * signed_volume({f[0], f[1], f[2], f[3], u}), 1e-12);
  // Normal to every edge of the facet.
  for (int i = 1; i < 4; ++i) {
    double along = 0;
    for (int k = 0; k < 4; ++k) along += n[k] * (f[i][k] - f[0][k]);
    EXPECT_NEAR(along, 0, 1e-12);
  }
}

TEST(Geometry, FacetCircumcenterIsEquidistantWithinItsHyperplane) {
  const Tetrahedron4 f{{{0.1, 0.2, 0.3, 0.4}, {1.3, 0.1, 0.2, 0.5}, {0.2, 1.1, 0.3, 0.1},
                        {0.4, 0.3, 1.7, 0.2}}};
  const Point4 c = facet_circumcenter(f);
  const Point4 n = hyperplane_normal(f);
  double off_plane = 0;
  for (int k = 0; k < 4; ++k) off_plane += n[k] * (c[k] - f[0][k]);
  EXPECT_NEAR(off_plane, 0, 1e-12);
  for (const Point4& p : f) EXPECT_NEAR(distance(c, p), distance(c, f[0]), 1e-12);
  // A flat facet has no circumcenter.
  const Tetrahedron4 flat{{{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {1, 1, 0, 0}}};
  EXPECT_FALSE(std::isfinite(facet_circumcenter(flat)[0]));
}

}  // namespace
}  // namespace mesh4d::delaunay
