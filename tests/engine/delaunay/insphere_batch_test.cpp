#include "delaunay/insphere_batch.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "delaunay/predicate_kernels.h"

namespace mesh4d::delaunay::detail {
namespace {

// Every group of four pentatopes (five points each) against q, both code paths, against
// insphere_semi_static() one at a time.
void expect_same_as_scalar(const std::vector<Point4>& points, const Point4& q) {
  ASSERT_EQ(points.size() % 20, 0u);
  for (std::size_t i = 0; i < points.size(); i += 20) {
    const Point4* vertices[4][5];
    for (int l = 0; l < 4; ++l)
      for (int k = 0; k < 5; ++k) vertices[l][k] = &points[i + 5 * l + k];
    for (bool portable : {false, true}) {
      int out[4];
      insphere_semi_static4(vertices, q, out, portable);
      for (int l = 0; l < 4; ++l)
        EXPECT_EQ(out[l], insphere_semi_static(vertices[l], q))
            << "group " << i / 20 << " lane " << l << (portable ? " (portable)" : "");
    }
  }
}

TEST(InsphereBatch, SameAnswersAsOneAtATime) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Point4> points(20 * 200);
  for (auto& p : points)
    for (double& x : p) x = unit(rng);
  int decided = 0;
  for (const Point4& q : {Point4{0.5, 0.5, 0.5, 0.5}, Point4{2, -1, 0.3, 0.1}}) {
    expect_same_as_scalar(points, q);
    for (std::size_t i = 0; i < points.size(); i += 5) {
      const Point4* s[5] = {&points[i], &points[i + 1], &points[i + 2], &points[i + 3],
                            &points[i + 4]};
      decided += insphere_semi_static(s, q) != kUndecided;
    }
  }
  EXPECT_GT(decided, 1000);  // the filter decides most of them: the lanes' signs were compared
}

TEST(InsphereBatch, GridAndCosphericalCasesUndecidedAlike) {
  // Grid points: co-spherical and co-planar sets (determinant exactly 0, undecided), and exact
  // ties of the bound.
  std::mt19937_64 rng(5);
  std::vector<Point4> points(20 * 100);
  for (auto& p : points)
    for (double& x : p) x = static_cast<double>(rng() % 3);
  int undecided = 0;
  for (const Point4& q : {Point4{1, 1, 1, 1}, Point4{0, 2, 1, 0}}) {
    expect_same_as_scalar(points, q);
    for (std::size_t i = 0; i < points.size(); i += 5) {
      const Point4* s[5] = {&points[i], &points[i + 1], &points[i + 2], &points[i + 3],
                            &points[i + 4]};
      undecided += insphere_semi_static(s, q) == kUndecided;
    }
  }
  EXPECT_GT(undecided, 10);  // the degenerate lanes were there
}

}  // namespace
}  // namespace mesh4d::delaunay::detail
