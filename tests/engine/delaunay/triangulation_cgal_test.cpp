// On general-position input the Delaunay triangulation is unique, so mesh4d and CGAL's dD
// Delaunay_triangulation must produce the same set of pentatopes (sorted vertex tuples).
#include <CGAL/Delaunay_triangulation.h>
#include <CGAL/Epick_d.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>

#include "delaunay/checker.h"
#include "delaunay/triangulation.h"
#include "point_sets.h"

namespace mesh4d::delaunay {
namespace {

using Kernel = CGAL::Epick_d<CGAL::Dimension_tag<4>>;
using CgalDelaunay = CGAL::Delaunay_triangulation<Kernel>;
using Tuple = std::array<std::size_t, 5>;

std::vector<Tuple> cgal_cells(const std::vector<Point4>& pts) {
  std::map<Point4, std::size_t> index;
  std::vector<Kernel::Point_d> cp;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    index[pts[i]] = i;
    cp.emplace_back(pts[i][0], pts[i][1], pts[i][2], pts[i][3]);
  }
  CgalDelaunay dt(4);
  dt.insert(cp.begin(), cp.end());
  std::vector<Tuple> out;
  for (auto c = dt.finite_full_cells_begin(); c != dt.finite_full_cells_end(); ++c) {
    Tuple t;
    for (int i = 0; i < 5; ++i) {
      const auto& p = c->vertex(i)->point();
      t[i] = index.at(Point4{p[0], p[1], p[2], p[3]});
    }
    std::sort(t.begin(), t.end());
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<Tuple> mesh4d_cells(const Triangulation& t, const std::vector<Point4>& pts) {
  std::map<Point4, std::size_t> index;
  for (std::size_t i = 0; i < pts.size(); ++i) index[pts[i]] = i;
  std::vector<Tuple> out;
  const auto& st = t.store();
  for (CellId c = 0; c < st.cell_slots(); ++c) {
    if (!st.is_live(c) || st.is_infinite(c)) continue;
    Tuple tuple;
    for (int i = 0; i < 5; ++i) tuple[i] = index.at(st.point(st.cell(c).v[i]));
    std::sort(tuple.begin(), tuple.end());
    out.push_back(tuple);
  }
  std::sort(out.begin(), out.end());
  return out;
}

class SameAsCgal : public ::testing::TestWithParam<std::pair<std::size_t, std::uint64_t>> {};

TEST_P(SameAsCgal, RandomPoints) {
  const auto [n, seed] = GetParam();
  const auto pts = mesh4d::testing::random_points(n, seed, -10, 10);
  Triangulation t;
  t.insert_all(pts);
  ASSERT_TRUE(check_triangulation(t).ok);
  const auto ours = mesh4d_cells(t, pts);
  const auto theirs = cgal_cells(pts);
  EXPECT_EQ(ours.size(), theirs.size()) << "n " << n << " seed " << seed;
  EXPECT_TRUE(ours == theirs) << "n " << n << " seed " << seed;
}

INSTANTIATE_TEST_SUITE_P(SizesAndSeeds, SameAsCgal,
                         ::testing::Values(std::pair<std::size_t, std::uint64_t>{50, 1},
                                           std::pair<std::size_t, std::uint64_t>{500, 2},
                                           std::pair<std::size_t, std::uint64_t>{2000, 3},
                                           std::pair<std::size_t, std::uint64_t>{8000, 4}));

TEST(SameAsCgalAfterRemovals, RemainingPointsTriangulateAlike) {
  // After removals, the result must be the Delaunay triangulation of the points that remain.
  auto pts = mesh4d::testing::random_points(600, 17, -10, 10);
  Triangulation t;
  const auto ids = t.insert_all(pts);
  std::vector<Point4> remaining;
  int removed = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (i % 3 == 0 && t.remove(ids[i])) {
      ++removed;
      continue;
    }
    remaining.push_back(pts[i]);
  }
  ASSERT_GT(removed, 100);  // a third of the points, less those on the hull
  ASSERT_TRUE(check_triangulation(t).ok);
  EXPECT_TRUE(mesh4d_cells(t, remaining) == cgal_cells(remaining));
}

TEST(SameAsCgalClustered, ClusteredPoints) {
  const auto pts = mesh4d::testing::clustered_points(2000, 5);
  Triangulation t;
  t.insert_all(pts);
  EXPECT_TRUE(mesh4d_cells(t, pts) == cgal_cells(pts));
}

}  // namespace
}  // namespace mesh4d::delaunay
