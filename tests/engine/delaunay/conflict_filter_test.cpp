// The in-sphere filter from circumballs (conflict_filter.h): its error bounds checked against
// exact rational circumcenters (CGAL::Gmpq), its answers against the exact predicate, and a
// triangulation built with it against one built without.
#include "delaunay/conflict_filter.h"

#include <CGAL/Gmpq.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "delaunay/checker.h"
#include "delaunay/circumballs.h"
#include "delaunay/geometry.h"
#include "delaunay/predicates.h"
#include "delaunay/triangulation.h"
#include "point_sets.h"

namespace mesh4d::delaunay {
namespace {

using Rational = CGAL::Gmpq;

// The exact circumcenter: 2 (p_i − p_0) · x = |p_i − p_0|², solved in rationals; false when
// the simplex is flat.
bool exact_circumcenter(const Simplex4& s, std::array<Rational, 4>* center) {
  std::vector<std::vector<Rational>> m(4, std::vector<Rational>(5));
  for (int i = 0; i < 4; ++i) {
    Rational b = 0;
    for (int j = 0; j < 4; ++j) {
      const Rational d = Rational(s[i + 1][j]) - Rational(s[0][j]);
      m[i][j] = 2 * d;
      b += d * d;
    }
    m[i][4] = b;
  }
  for (int col = 0; col < 4; ++col) {
    int pivot = col;
    while (pivot < 4 && m[pivot][col] == 0) ++pivot;
    if (pivot == 4) return false;
    std::swap(m[pivot], m[col]);
    for (int r = 0; r < 4; ++r) {
      if (r == col || m[r][col] == 0) continue;
      const Rational f = m[r][col] / m[col][col];
      for (int c = col; c < 5; ++c) m[r][c] -= f * m[col][c];
    }
  }
  for (int j = 0; j < 4; ++j) (*center)[j] = Rational(s[0][j]) + m[j][4] / m[j][j];
  return true;
}

// Random, nearly flat, far from the origin, tiny, and grid simplices.
std::vector<Simplex4> test_simplices() {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Simplex4> out;
  for (int i = 0; i < 600; ++i) {
    const double offset = i % 3 == 0 ? 0 : i % 3 == 1 ? 1e4 : 37.5;
    const double size = i % 5 == 0 ? 1e-3 : i % 5 == 1 ? 100 : 1;
    Simplex4 s;
    for (auto& p : s)
      for (double& x : p) x = offset + size * unit(rng);
    if (i % 7 == 0) s[4][3] = s[3][3] + 1e-13 * size;  // a sliver
    if (i % 11 == 0) s[4] = {s[1][0], s[1][1], s[1][2], s[2][3]};
    if (i % 13 == 0)
      for (auto& p : s) p[3] = offset;  // flat
    out.push_back(s);
  }
  for (int i = 0; i < 200; ++i) {
    Simplex4 s;
    for (auto& p : s)
      for (double& x : p) x = static_cast<double>(rng() % 3);
    out.push_back(s);
  }
  // Down where products would be subnormal: no bound claimed (checked below).
  for (int i = 0; i < 4; ++i) {
    Simplex4 s;
    for (auto& p : s)
      for (double& x : p) x = 1e-60 * unit(rng);
    out.push_back(s);
  }
  return out;
}

std::vector<Circumball> balls_of(const std::vector<Simplex4>& simplices) {
  std::vector<Circumball> out(simplices.size());
  for (std::size_t i = 0; i < simplices.size(); i += 4) {
    const Point4* vertices[4][5];
    for (int l = 0; l < 4; ++l)
      for (int k = 0; k < 5; ++k)
        vertices[l][k] = &simplices[std::min(i + l, simplices.size() - 1)][k];
    Circumball balls[4];
    circumballs4(vertices, balls);
    for (std::size_t l = 0; l < 4 && i + l < simplices.size(); ++l) out[i + l] = balls[l];
  }
  return out;
}

TEST(ConflictFilter, CenterErrorBoundsTheExactCircumcenterAndRadius) {
  const auto simplices = test_simplices();
  const auto balls = balls_of(simplices);
  int bounded = 0, tight = 0;
  for (std::size_t i = 0; i < simplices.size(); ++i) {
    const Circumball& b = balls[i];
    std::array<Rational, 4> c;
    const bool solid = exact_circumcenter(simplices[i], &c);
    if (!solid) {
      EXPECT_TRUE(std::isinf(b.center_error)) << "flat simplex " << i;
      continue;
    }
    if (i + 4 >= simplices.size()) {
      EXPECT_TRUE(std::isinf(b.center_error)) << "subnormal range, simplex " << i;
    }
    if (!std::isfinite(b.center_error)) continue;
    ++bounded;
    Rational off2 = 0, r2 = 0;
    for (int j = 0; j < 4; ++j) {
      const Rational d = Rational(b.center[j]) - c[j];
      off2 += d * d;
      const Rational e = Rational(simplices[i][0][j]) - c[j];
      r2 += e * e;
    }
    const Rational e(b.center_error);
    EXPECT_LE(off2, e * e) << "simplex " << i;
    // The radius: within center_error plus 11 units of its last place.
    const double slack = b.center_error + 11 * 0x1p-53 * b.radius;
    const Rational hi(b.radius + slack), lo(std::max(0.0, b.radius - slack));
    EXPECT_LE(r2, hi * hi) << "simplex " << i;
    EXPECT_GE(r2, lo * lo) << "simplex " << i;
    if (b.center_error < 1e-9 * b.radius) ++tight;
  }
  // Not a bound that decides nothing: nearly every solid simplex gets a tight one.
  EXPECT_GT(bounded, 600);
  EXPECT_GT(tight, bounded * 9 / 10);
}

TEST(ConflictFilter, VerdictsAgreeWithTheExactPredicate) {
  const auto simplices = test_simplices();
  const auto balls = balls_of(simplices);
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> unit(-1, 1);
  long decided = 0, clear = 0, clear_decided = 0;
  for (std::size_t i = 0; i < simplices.size(); ++i) {
    Simplex4 s = simplices[i];
    const int o = orient4(s[0], s[1], s[2], s[3], s[4]);
    const Circumball& b = balls[i];
    std::vector<Point4> queries;
    std::vector<bool> clear_of_sphere;  // at least a millionth of the radius from it
    // Around the sphere at relative distances down to the last place, and exactly on it.
    for (double t : {0.5, 1e-3, 1e-6, 1e-9, 1e-12, 1e-14, 1e-15, 0.0, -1e-15, -1e-14, -1e-12, -1e-9,
                     -1e-6, -1e-3, -0.5}) {
      if (!std::isfinite(b.radius)) break;
      Point4 dir{unit(rng), unit(rng), unit(rng), unit(rng)};
      double n = 0;
      for (double x : dir) n += x * x;
      n = std::sqrt(n);
      Point4 q;
      for (int j = 0; j < 4; ++j) q[j] = b.center[j] + dir[j] / n * b.radius * (1 + t);
      queries.push_back(q);
      clear_of_sphere.push_back(std::abs(t) >= 1e-6);
    }
    for (const Point4& v : s) queries.push_back(v);  // on the sphere exactly
    for (int k = 0; k < 4; ++k) {                    // grid points
      Point4 q;
      for (double& x : q) x = static_cast<double>(rng() % 3);
      queries.push_back(q);
    }
    if (o < 0) std::swap(s[0], s[1]);  // insphere4 wants positive orientation; the ball is the same
    const Point4* sp[5] = {&s[0], &s[1], &s[2], &s[3], &s[4]};
    for (std::size_t k = 0; k < queries.size(); ++k) {
      const Point4& q = queries[k];
      const int verdict = ball_verdict(b.center, b.radius, b.center_error, q);
      if (o == 0) {
        EXPECT_EQ(verdict, 0) << "flat simplex " << i;
        continue;
      }
      const bool is_clear = k < clear_of_sphere.size() && clear_of_sphere[k];
      clear += is_clear;
      if (verdict == 0) continue;
      ++decided;
      clear_decided += is_clear;
      EXPECT_EQ(verdict, insphere4(sp, q)) << "simplex " << i;
    }
  }
  // Not a filter that decides nothing: nearly every query clear of the sphere is decided.
  EXPECT_GT(decided, 5000);
  EXPECT_GT(clear_decided, clear * 9 / 10);
}

// A filter that measures each pentatope when asked (the refiner keeps the balls instead).
class MeasuringFilter final : public ConflictFilter {
 public:
  explicit MeasuringFilter(const Triangulation& t) : t_(t) {}
  void decide(const CellId* cells, int count, const Point4& p,
              std::int8_t* verdict) const override {
    const PentatopeStore& st = t_.store();
    for (int k = 0; k < count; ++k) {
      verdict[k] = 0;
      if (st.is_infinite(cells[k])) continue;
      const Point4* vertices[4][5];
      for (int l = 0; l < 4; ++l)
        for (int i = 0; i < 5; ++i) vertices[l][i] = &st.point(st.cell(cells[k]).v[i]);
      Circumball balls[4];
      circumballs4(vertices, balls);
      verdict[k] = static_cast<std::int8_t>(
          ball_verdict(balls[0].center, balls[0].radius, balls[0].center_error, p));
      ++(verdict[k] != 0 ? decided : undecided);
    }
  }
  void prefetch(const CellId*, int) const override {}
  mutable long decided = 0, undecided = 0;

 private:
  const Triangulation& t_;
};

std::set<std::array<VertexId, 5>> pentatopes_of(const Triangulation& t) {
  std::set<std::array<VertexId, 5>> out;
  for (CellId c = 0; c < t.store().cell_slots(); ++c) {
    if (!t.store().is_live(c)) continue;
    std::array<VertexId, 5> v;
    std::copy(t.store().cell(c).v, t.store().cell(c).v + 5, v.begin());
    std::sort(v.begin(), v.end());
    out.insert(v);
  }
  return out;
}

TEST(ConflictFilter, TriangulationIsTheSameWithTheFilter) {
  std::vector<std::vector<Point4>> sets = {testing::random_points(3000, 5),
                                           testing::clustered_points(1500, 6), testing::lattice(5),
                                           testing::cospherical_points(9)};
  for (std::size_t k = 0; k < sets.size(); ++k) {
    Triangulation plain, filtered;
    MeasuringFilter filter(filtered);
    filtered.set_conflict_filter(&filter);
    for (const Point4& p : sets[k]) {
      plain.insert(p);
      filtered.insert(p);
    }
    EXPECT_TRUE(check_triangulation(filtered).ok) << "set " << k;
    EXPECT_EQ(pentatopes_of(plain), pentatopes_of(filtered)) << "set " << k;
    EXPECT_GT(filter.decided, 0) << "set " << k;
    if (k == 0) {
      EXPECT_GT(filter.decided, 100 * filter.undecided);  // generic input
    }
    if (k >= 2) {
      EXPECT_GT(filter.undecided, 0) << "set " << k;  // ties go to the predicates
    }
  }
}

}  // namespace
}  // namespace mesh4d::delaunay
