// FeatureIndex against a brute-force scan: the refiner's R1 decisions depend on its answers.
#include "refine/feature_index.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace mesh4d::refine {
namespace {

bool brute_within(const std::vector<Point4>& points, const Point4& p, double r) {
  for (const Point4& q : points) {
    double d2 = 0;
    for (int a = 0; a < 4; ++a) d2 += (p[a] - q[a]) * (p[a] - q[a]);
    if (d2 < r * r) return true;
  }
  return false;
}

// n random points with coordinates in [-extent, extent] (the last axis scaled by time_scale),
// added to `index` and returned.
std::vector<Point4> add_random_points(FeatureIndex& index, int n, double extent, double time_scale,
                                      std::mt19937_64& rng) {
  std::uniform_real_distribution<double> coordinate(-extent, extent);
  std::vector<Point4> points;
  for (int i = 0; i < n; ++i) {
    Point4 p{coordinate(rng), coordinate(rng), coordinate(rng), time_scale * coordinate(rng)};
    index.add(p);
    points.push_back(p);
  }
  return points;
}

TEST(FeatureIndex, AgreesWithABruteForceScan) {
  // Enough points to grow the table several times; queries at every radius up to the cell size,
  // around the points (hits and near misses) and anywhere (mostly misses), negative
  // coordinates included.
  const double cell = 1.5;
  FeatureIndex index(cell);
  std::mt19937_64 rng(7);
  const std::vector<Point4> points = add_random_points(index, 5000, 20, 0.1, rng);
  std::uniform_real_distribution<double> coordinate(-20, 20), offset(-1, 1), radius(0, cell);
  EXPECT_EQ(index.size(), points.size());
  int hits = 0, misses = 0;
  for (int i = 0; i < 20000; ++i) {
    Point4 p;
    if (i % 2) {
      p = points[rng() % points.size()];
      for (double& x : p) x += offset(rng);
    } else {
      p = {coordinate(rng), coordinate(rng), coordinate(rng), coordinate(rng)};
    }
    const double r = radius(rng);
    const bool expected = brute_within(points, p, r);
    ASSERT_EQ(index.any_within(p, r), expected) << "query " << i;
    (expected ? hits : misses)++;
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, 1000);
}

TEST(FeatureIndex, StrictlyWithinAndExactPoints) {
  FeatureIndex index(1.0);
  EXPECT_FALSE(index.any_within({0, 0, 0, 0}, 1.0));
  index.add({0.5, 0, 0, 0});
  EXPECT_TRUE(index.any_within({0.5, 0, 0, 0}, 1e-9));  // the point itself
  EXPECT_FALSE(index.any_within({1.5, 0, 0, 0}, 1.0));  // at distance exactly r: not within
  EXPECT_TRUE(index.any_within({1.4, 0, 0, 0}, 1.0));   // across a cell boundary
  EXPECT_TRUE(index.any_within({-0.4, 0, 0, 0}, 1.0));  // a negative cell
}

TEST(FeatureIndex, OwnCellSearchesFindOnlyTrueAnswers) {
  // The shortcuts' partial searches: a yes is a point within r that passes the test, and a
  // point in p's own cell that does is always found.
  const double cell = 2.0;
  FeatureIndex index(cell);
  std::mt19937_64 rng(3);
  const std::vector<Point4> points = add_random_points(index, 2000, 10, 1, rng);
  std::uniform_real_distribution<double> offset(-1, 1), radius(0, cell);
  const auto same_cell = [&](const Point4& a, const Point4& b) {
    for (int k = 0; k < 4; ++k)
      if (std::floor(a[k] / cell) != std::floor(b[k] / cell)) return false;
    return true;
  };
  int found = 0;
  for (int i = 0; i < 5000; ++i) {
    Point4 p = points[rng() % points.size()];
    for (double& x : p) x += offset(rng);
    const double r = radius(rng);
    // Accept only points above a random hyperplane through p.
    const double t = offset(rng);
    const auto above = [&](const Point4& q) { return q[0] - p[0] > t * (q[1] - p[1]); };
    bool expected = false;
    for (const Point4& q : points) {
      double d2 = 0;
      for (int a = 0; a < 4; ++a) d2 += (p[a] - q[a]) * (p[a] - q[a]);
      expected = expected || (d2 < r * r && above(q) && same_cell(p, q));
    }
    ASSERT_EQ(index.any_within_own_cell_such(p, r, above), expected) << "query " << i;
    found += expected;
  }
  EXPECT_GT(found, 200);
}

TEST(FeatureIndex, FarCellsSharingAKeyStayCorrect) {
  // Cells 2^16 apart share a key: their points share a list, and distances still decide.
  FeatureIndex index(1.0);
  index.add({0.5, 0.5, 0.5, 0.5});
  EXPECT_FALSE(index.any_within({65536.5, 0.5, 0.5, 0.5}, 0.9));
  index.add({65536.5, 0.5, 0.5, 0.5});
  EXPECT_TRUE(index.any_within({65536.6, 0.5, 0.5, 0.5}, 0.9));
  EXPECT_TRUE(index.any_within({0.6, 0.5, 0.5, 0.5}, 0.9));
}

}  // namespace
}  // namespace mesh4d::refine
