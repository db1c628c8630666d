// FeatureIndex against a brute-force scan: the refiner's R1 decisions depend on its answers.
#include "refine/feature_index.h"

#include <gtest/gtest.h>

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

TEST(FeatureIndex, AgreesWithABruteForceScan) {
  // Enough points to grow the table several times; queries at every radius up to the cell size,
  // around the points (hits and near misses) and anywhere (mostly misses), negative
  // coordinates included.
  const double cell = 1.5;
  FeatureIndex index(cell);
  std::vector<Point4> points;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coordinate(-20, 20), offset(-1, 1), radius(0, cell);
  for (int i = 0; i < 5000; ++i) {
    Point4 p{coordinate(rng), coordinate(rng), coordinate(rng), 0.1 * coordinate(rng)};
    index.add(p);
    points.push_back(p);
  }
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
