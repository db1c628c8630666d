// The filtered predicates against an independent exact reference: rational Gaussian elimination
// (CGAL::Gmpq), a different algorithm and number type from the predicates' own exact path.
#include "delaunay/predicates.h"

#include <CGAL/Gmpq.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace mesh4d::delaunay {
namespace {

using Rational = CGAL::Gmpq;
using Matrix = std::vector<std::vector<Rational>>;

int reference_det_sign(Matrix m) {
  const std::size_t n = m.size();
  int sign = 1;
  for (std::size_t col = 0; col < n; ++col) {
    std::size_t pivot = col;
    while (pivot < n && m[pivot][col] == 0) ++pivot;
    if (pivot == n) return 0;
    if (pivot != col) {
      std::swap(m[pivot], m[col]);
      sign = -sign;
    }
    if (m[col][col] < 0) sign = -sign;
    for (std::size_t r = col + 1; r < n; ++r) {
      const Rational f = m[r][col] / m[col][col];
      for (std::size_t c = col; c < n; ++c) m[r][c] -= f * m[col][c];
    }
  }
  return sign;
}

int reference_orient(const Point4* const p[5]) {
  Matrix m(4, std::vector<Rational>(4));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m[i][j] = Rational((*p[i + 1])[j]) - Rational((*p[0])[j]);
  return reference_det_sign(m);
}

int reference_insphere(const Point4* const s[5], const Point4& q) {
  Matrix m(5, std::vector<Rational>(5));
  for (int i = 0; i < 5; ++i) {
    Rational w = 0;
    for (int j = 0; j < 4; ++j) {
      m[i][j] = Rational((*s[i])[j]) - Rational(q[j]);
      w += m[i][j] * m[i][j];
    }
    m[i][4] = w;
  }
  return reference_det_sign(m);
}

int orient_of(const Point4* const p[5]) {
  return orient4(*p[0], *p[1], *p[2], *p[3], *p[4]);
}

Point4 random_point(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return {u(rng), u(rng), u(rng), u(rng)};
}

// a + u(b-a) + v(c-a) + w(d-a), rounded: on the hyperplane of a..d up to rounding.
Point4 near_hyperplane(const Point4& a, const Point4& b, const Point4& c, const Point4& d,
                       std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 2.0);
  const double x = u(rng), y = u(rng), z = u(rng);
  Point4 p;
  for (int j = 0; j < 4; ++j)
    p[j] = a[j] + x * (b[j] - a[j]) + y * (c[j] - a[j]) + z * (d[j] - a[j]);
  return p;
}

// A point on the unit 3-sphere, rounded: co-spherical with others up to rounding.
Point4 near_sphere(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  Point4 p{g(rng), g(rng), g(rng), g(rng)};
  const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3]);
  for (double& c : p) c /= r;
  return p;
}

const Point4 kUnitSimplex[5] = {
    {0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};

TEST(Orient4, SignOfUnitSimplexAndSwaps) {
  const auto& s = kUnitSimplex;
  EXPECT_EQ(orient4(s[0], s[1], s[2], s[3], s[4]), 1);
  EXPECT_EQ(orient4(s[0], s[2], s[1], s[3], s[4]), -1);
  EXPECT_EQ(orient4(s[1], s[0], s[2], s[3], s[4]), -1);
  const Point4 on_facet{0.25, 0.25, 0.25, 0.0};  // in the hyperplane t = 0 of s[0..3]
  EXPECT_EQ(orient4(s[0], s[1], s[2], s[3], on_facet), 0);
}

TEST(Orient4, MatchesExactReferenceOnRandomAndNearDegenerateInput) {
  std::mt19937_64 rng(12345);
  const auto before = predicate_counters().orient_double_double;
  for (int trial = 0; trial < 3000; ++trial) {
    Point4 p[5];
    for (int i = 0; i < 4; ++i) p[i] = random_point(rng);
    p[4] = (trial % 3 == 0) ? random_point(rng) : near_hyperplane(p[0], p[1], p[2], p[3], rng);
    const Point4* ptrs[5] = {&p[0], &p[1], &p[2], &p[3], &p[4]};
    ASSERT_EQ(orient_of(ptrs), reference_orient(ptrs)) << "seed 12345, trial " << trial;
  }
  // The near-degenerate cases must have defeated the double filters, or this proves little.
  EXPECT_GT(predicate_counters().orient_double_double, before);
}

TEST(Orient4, MatchesExactReferenceOnIntegerGrid) {
  std::mt19937_64 rng(777);
  std::uniform_int_distribution<int> coord(0, 3);
  int zeros = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    Point4 p[5];
    for (auto& pt : p)
      for (double& c : pt) c = coord(rng) * 0.1;  // 0.1 is inexact: a grid with rounding
    const Point4* ptrs[5] = {&p[0], &p[1], &p[2], &p[3], &p[4]};
    const int ref = reference_orient(ptrs);
    ASSERT_EQ(orient_of(ptrs), ref) << "seed 777, trial " << trial;
    zeros += (ref == 0);
  }
  EXPECT_GT(zeros, 100);  // grid input is full of exact degeneracies
}

TEST(Predicates, ExactZerosOfInexactProductsReachTheMultiprecisionStage) {
  // A repeated point among random doubles: the determinant is exactly zero, but no product is
  // exact, so neither double-double nor intervals can prove it; only the last stage can.
  std::mt19937_64 rng(31);
  auto& counters = predicate_counters();
  const auto orient_before = counters.orient_exact;
  const auto insphere_before = counters.insphere_exact;
  for (int trial = 0; trial < 50; ++trial) {
    Point4 p[5];
    for (auto& pt : p) pt = random_point(rng);
    EXPECT_EQ(orient4(p[0], p[1], p[2], p[3], p[1]), 0);
    // A simplex with a repeated vertex: two equal rows, so the lifted determinant is zero.
    const Point4* s[5] = {&p[0], &p[1], &p[2], &p[3], &p[1]};
    EXPECT_EQ(insphere4(s, p[4]), 0);
  }
  EXPECT_GT(counters.orient_exact, orient_before);
  EXPECT_GT(counters.insphere_exact, insphere_before);
}

TEST(Insphere4, InsideOnOutside) {
  const Point4* s[5] = {&kUnitSimplex[0], &kUnitSimplex[1], &kUnitSimplex[2], &kUnitSimplex[3],
                        &kUnitSimplex[4]};
  EXPECT_EQ(insphere4(s, Point4{0.2, 0.2, 0.2, 0.2}), 1);
  EXPECT_EQ(insphere4(s, Point4{5, 5, 5, 5}), -1);
  // (1, 1, 0, 0) lies on the circumsphere (center (½,½,½,½), radius 1).
  EXPECT_EQ(insphere4(s, Point4{1, 1, 0, 0}), 0);
}

TEST(Insphere4, MatchesExactReferenceOnNearCosphericalInput) {
  std::mt19937_64 rng(4242);
  const auto before = predicate_counters().insphere_double_double;
  int checked = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    Point4 p[6];
    for (auto& pt : p) pt = (trial % 4 == 0) ? random_point(rng) : near_sphere(rng);
    const Point4* s[5] = {&p[0], &p[1], &p[2], &p[3], &p[4]};
    const int o = reference_orient(s);
    if (o == 0) continue;
    if (o < 0) std::swap(s[0], s[1]);
    ASSERT_EQ(insphere4(s, p[5]), reference_insphere(s, p[5])) << "seed 4242, trial " << trial;
    ++checked;
  }
  EXPECT_GT(checked, 2900);
  EXPECT_GT(predicate_counters().insphere_double_double, before);
}

// Every vertex subset of a small lattice: orientation, exact in-sphere and the tie-break.
class GridSos : public ::testing::Test {
 protected:
  void SetUp() override {
    for (int i = 0; i < 81; ++i)
      grid_.push_back({double(i % 3), double(i / 3 % 3), double(i / 9 % 3), double(i / 27)});
  }
  std::vector<Point4> grid_;
};

TEST_F(GridSos, TieBreakIsNeverZeroAndAgreesWithExactSign) {
  std::mt19937_64 rng(99);
  std::uniform_int_distribution<int> pick(0, 80);
  int ties = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    VertexId ids[6];
    for (auto& id : ids) id = pick(rng);
    std::sort(ids, ids + 6);
    if (std::adjacent_find(ids, ids + 6) != ids + 6) continue;  // distinct points only
    std::shuffle(ids, ids + 6, rng);
    const Point4* s[5];
    VertexId sid[5];
    for (int i = 0; i < 5; ++i) {
      s[i] = &grid_[ids[i]];
      sid[i] = ids[i];
    }
    const int o = orient_of(s);
    if (o == 0) continue;
    if (o < 0) {
      std::swap(s[0], s[1]);
      std::swap(sid[0], sid[1]);
    }
    const int exact = insphere4(s, grid_[ids[5]]);
    const int sos = insphere4_sos(s, sid, grid_[ids[5]], ids[5]);
    ASSERT_NE(sos, 0) << "seed 99, trial " << trial;
    if (exact != 0) {
      ASSERT_EQ(sos, exact);
    }
    ties += (exact == 0);

    // The perturbation belongs to the points, not to their places in the call: an even
    // permutation of the simplex (a 5-cycle) keeps the answer, an odd one (a swap) negates the
    // determinant and hence the answer.
    const Point4* rot[5] = {s[1], s[2], s[3], s[4], s[0]};
    const VertexId rot_id[5] = {sid[1], sid[2], sid[3], sid[4], sid[0]};
    ASSERT_EQ(insphere4_sos(rot, rot_id, grid_[ids[5]], ids[5]), sos);
    const Point4* swp[5] = {s[1], s[0], s[2], s[3], s[4]};
    const VertexId swp_id[5] = {sid[1], sid[0], sid[2], sid[3], sid[4]};
    ASSERT_EQ(insphere4_sos(swp, swp_id, grid_[ids[5]], ids[5]), -sos);
  }
  EXPECT_GT(ties, 100);
}

TEST(Insphere4Sos, NewestCosphericalPointIsOutside) {
  // Corners of the unit tesseract are co-spherical; a simplex of corners and a sixth corner tie.
  const Point4 c[6] = {{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0},
                       {0, 0, 1, 0}, {0, 0, 0, 1}, {1, 1, 1, 1}};
  const Point4* s[5] = {&c[0], &c[1], &c[2], &c[3], &c[4]};
  const VertexId ids[5] = {0, 1, 2, 3, 4};
  ASSERT_EQ(insphere4(s, c[5]), 0);
  EXPECT_EQ(insphere4_sos(s, ids, c[5], 5), -1);
  // The same sixth point, older than every simplex vertex, is inside.
  const VertexId newer_ids[5] = {10, 11, 12, 13, 14};
  EXPECT_EQ(insphere4_sos(s, newer_ids, c[5], 5), 1);
}

}  // namespace
}  // namespace mesh4d::delaunay
