// Insertion: the checker after every insertion on small inputs, at the end on larger ones.
#include "delaunay/triangulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "delaunay/checker.h"
#include "delaunay/geometry.h"
#include "point_sets.h"

namespace mesh4d::delaunay {
namespace {

using mesh4d::testing::clustered_points;
using mesh4d::testing::cospherical_points;
using mesh4d::testing::lattice;
using mesh4d::testing::random_points;

// Inserts one by one (in the given order), checking after each insertion.
void insert_checking_each(Triangulation& t, const std::vector<Point4>& pts) {
  CellId hint = kNoCell;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto r = t.insert(pts[i], VertexKind::free, hint);
    if (r.cell != kNoCell) hint = r.cell;
    const CheckResult check = check_triangulation(t);
    ASSERT_TRUE(check.ok) << "after point " << i << ": " << check.error;
  }
}

TEST(Triangulation, RandomPointsValidAfterEveryInsertion) {
  for (std::uint64_t seed : {1, 2, 3}) {
    Triangulation t;
    insert_checking_each(t, random_points(120, seed));
    EXPECT_EQ(t.number_of_vertices(), 120u) << "seed " << seed;
    EXPECT_EQ(t.dimension(), 4);
  }
}

TEST(Triangulation, ClusteredPointsValid) {
  Triangulation t;
  insert_checking_each(t, clustered_points(150, 7));
  Triangulation big;
  big.insert_all(clustered_points(3000, 8));
  const CheckResult check = check_triangulation(big);
  EXPECT_TRUE(check.ok) << check.error;
}

TEST(Triangulation, SmallLatticeValidAfterEveryInsertion) {
  auto pts = lattice(3);
  std::shuffle(pts.begin(), pts.end(), std::mt19937_64(5));
  Triangulation t;
  insert_checking_each(t, pts);
  EXPECT_EQ(t.number_of_vertices(), 81u);
}

TEST(Triangulation, SixLatticeIsValidAndFillsTheHypercube) {
  // All 1296 points of the 6⁴ lattice: co-spherical in every unit cube, co-hyperplanar on every
  // face. The finite pentatopes must tile [0, 5]⁴: their volumes sum to 5⁴.
  Triangulation t;
  const auto pts = lattice(6);
  t.insert_all(pts);
  const CheckResult check = check_triangulation(t);
  ASSERT_TRUE(check.ok) << check.error;
  EXPECT_EQ(t.number_of_vertices(), 1296u);
  double volume = 0;
  const auto& st = t.store();
  for (CellId c = 0; c < st.cell_slots(); ++c) {
    if (!st.is_live(c) || st.is_infinite(c)) continue;
    Simplex4 simplex;
    for (int i = 0; i < 5; ++i) simplex[i] = st.point(st.cell(c).v[i]);
    const double v = signed_volume(simplex);
    EXPECT_GT(v, 0);
    volume += v;
  }
  EXPECT_NEAR(volume, 625.0, 1e-9);
}

TEST(Triangulation, CosphericalPointsValidAfterEveryInsertion) {
  auto pts = cospherical_points(9);  // integer points on the sphere of radius 3, and ±1 corners
  ASSERT_GT(pts.size(), 100u);
  std::shuffle(pts.begin(), pts.end(), std::mt19937_64(11));
  Triangulation t;
  insert_checking_each(t, pts);
  EXPECT_EQ(t.number_of_vertices(), pts.size());
}

TEST(Triangulation, DuplicatePointsReturnTheExistingVertexAndChangeNothing) {
  const auto pts = random_points(200, 21);
  Triangulation t;
  const auto ids = t.insert_all(pts);
  const std::size_t cells = t.number_of_cells();
  for (std::size_t i = 0; i < pts.size(); i += 7) {
    const auto r = t.insert(pts[i]);
    EXPECT_FALSE(r.inserted);
    EXPECT_EQ(r.vertex, ids[i]);
  }
  EXPECT_EQ(t.number_of_cells(), cells);
  EXPECT_EQ(t.number_of_vertices(), 200u);
  EXPECT_TRUE(check_triangulation(t).ok);
}

TEST(Triangulation, DuplicatesWhileWaitingForTheFirstSimplex) {
  Triangulation t;
  EXPECT_TRUE(t.insert({0, 0, 0, 0}).inserted);
  EXPECT_FALSE(t.insert({0, 0, 0, 0}).inserted);
  EXPECT_EQ(t.number_of_vertices(), 1u);
  EXPECT_EQ(t.dimension(), -1);
}

TEST(Triangulation, DegenerateStartWaitsUntilFourDimensional) {
  // Twenty points in the hyperplane t = 0 (and collinear ones among them), then one off it.
  Triangulation t;
  for (int i = 0; i < 5; ++i) t.insert({double(i), 0, 0, 0});
  for (const auto& p : random_points(15, 3)) t.insert({p[0], p[1], p[2], 0});
  EXPECT_EQ(t.dimension(), -1);
  EXPECT_EQ(t.any_cell(), kNoCell);
  t.insert({0.5, 0.5, 0.5, 1.0});
  ASSERT_EQ(t.dimension(), 4);
  EXPECT_EQ(t.number_of_vertices(), 21u);
  const CheckResult check = check_triangulation(t);
  EXPECT_TRUE(check.ok) << check.error;
}

TEST(Triangulation, NonFinitePointIsRejected) {
  Triangulation t;
  EXPECT_THROW(t.insert({0, std::nan(""), 0, 0}), std::invalid_argument);
  EXPECT_THROW(t.insert({0, 0, INFINITY, 0}), std::invalid_argument);
}

TEST(Triangulation, LargerRandomSetValidAtTheEnd) {
  Triangulation t;
  t.insert_all(random_points(5000, 99));
  const CheckResult check = check_triangulation(t);
  EXPECT_TRUE(check.ok) << check.error;
  // For uniform points in 4D, about 31 pentatopes per point (BUILD-NOTES: 29-34).
  const double per_point = double(t.number_of_finite_cells()) / 5000;
  EXPECT_GT(per_point, 20);
  EXPECT_LT(per_point, 40);
}

}  // namespace
}  // namespace mesh4d::delaunay
