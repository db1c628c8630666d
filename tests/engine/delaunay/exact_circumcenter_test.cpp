// The circumcenter from exact determinants, for pentatopes that double arithmetic calls flat.
#include "delaunay/exact_circumcenter.h"

#include <gtest/gtest.h>

#include <cmath>

#include "delaunay/geometry.h"
#include "delaunay/predicates.h"

namespace mesh4d::delaunay {
namespace {

// Four feature points of a refinement on voxel-grid coordinates, nearly on one 2-plane (the
// frame times carry a rounding), and a free vertex: found in a parallel refinement of the
// merging blobs, where the double determinant rounds to zero.
Simplex4 nearly_flat() {
  return {{{36, 17, 17, 3.5299999999963623},
           {36, 20, 18, 2.5299999999963623},
           {37, 16, 19, 2.5299999999963623},
           {32.900112888041726, 17.366687198657118, 19.096635906583103, 1.6797198143089771},
           {37, 19, 20, 1.529999999996362}}};
}

std::optional<Point4> exact_of(const Simplex4& s) {
  const Point4* p[5] = {&s[0], &s[1], &s[2], &s[3], &s[4]};
  return exact_circumcenter(p);
}

TEST(ExactCircumcenter, AgreesWithTheDoubleOneOnAWellShapedPentatope) {
  const Simplex4 s{{{0.1, 0.2, 0.3, 0.4},
                    {1.3, 0.1, 0.2, 0.5},
                    {0.2, 1.1, 0.3, 0.1},
                    {0.4, 0.3, 1.7, 0.2},
                    {0.3, 0.2, 0.1, 0.9}}};
  const auto exact = exact_of(s);
  ASSERT_TRUE(exact);
  const Point4 c = circumcenter(s);
  for (int j = 0; j < 4; ++j) EXPECT_NEAR((*exact)[j], c[j], 1e-12);
}

TEST(ExactCircumcenter, FindsTheBallOfAPentatopeTheDoublesCallFlat) {
  const Simplex4 s = nearly_flat();
  ASSERT_EQ(orient4(s[0], s[1], s[2], s[3], s[4]), 1);  // not flat: a pentatope of a mesh
  EXPECT_FALSE(std::isfinite(circumcenter(s)[0]));
  const auto c = exact_of(s);
  ASSERT_TRUE(c);
  // The exact in-sphere predicate judges the ball, independently of the construction: s₀'s
  // antipode lies on the sphere, so a point a millionth of the diameter short of it is inside
  // and one a millionth past it outside.
  const Point4* p[5] = {&s[0], &s[1], &s[2], &s[3], &s[4]};
  for (double t : {1 - 1e-6, 1 + 1e-6}) {
    Point4 q;
    for (int j = 0; j < 4; ++j) q[j] = s[0][j] + 2 * t * ((*c)[j] - s[0][j]);
    EXPECT_EQ(insphere4(p, q), t < 1 ? 1 : -1) << "t " << t;
  }
}

TEST(ExactCircumcenter, HasNoneForAFlatSimplex) {
  const Simplex4 s{{{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {1, 1, 1, 0}}};
  EXPECT_FALSE(exact_of(s));
}

}  // namespace
}  // namespace mesh4d::delaunay
