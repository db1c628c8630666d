// Internal to the predicates: the determinant expressions (templates on the number type, so
// that every filter stage evaluates the very same expression tree its error bound counts), and
// the first, semi-static stage of in-sphere, inline so that cavity search can call it without a
// function call per pentatope. Users call predicates.h.
#pragma once

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "delaunay/point4.h"

namespace mesh4d::delaunay::detail {

inline constexpr int kUndecided = 2;

// Expression depths (one level per rounded operation on the longest path, the leaf difference
// included), used by every stage's error bound.
inline constexpr int kOrientDepth = 9;     // diff 1, 2x2 minor 3, minor product 4, sum of 6: 9
inline constexpr int kInsphereDepth = 14;  // diff 1, |b|² 5, 4x4 minor 9, w·minor 10, sum: 14

// 4×4 determinant by Laplace expansion along rows 0 and 1: six products of complementary 2×2
// minors, summed left to right (the depth above counts this order).
template <class NT>
inline NT det4(const NT m[4][4]) {
  auto minor2 = [&](int r, int c0, int c1) {
    return m[r][c0] * m[r + 1][c1] - m[r][c1] * m[r + 1][c0];
  };
  const NT a01 = minor2(0, 0, 1), a02 = minor2(0, 0, 2), a03 = minor2(0, 0, 3);
  const NT a12 = minor2(0, 1, 2), a13 = minor2(0, 1, 3), a23 = minor2(0, 2, 3);
  const NT b01 = minor2(2, 0, 1), b02 = minor2(2, 0, 2), b03 = minor2(2, 0, 3);
  const NT b12 = minor2(2, 1, 2), b13 = minor2(2, 1, 3), b23 = minor2(2, 2, 3);
  return a01 * b23 - a02 * b13 + a03 * b12 + a12 * b03 - a13 * b02 + a23 * b01;
}

// det[b_i, |b_i|²] (5×5) with b_i = s_i - q, expanded along the lifted column:
// Σ_i (-1)^i |b_i|² M_i, where M_i = det4(b without row i) comes from the 2×2 minors of every row
// pair in columns (x, y) and (z, t), shared by the five M_i (generalized Laplace expansion): 20
// minors and 30 products instead of 5 × 18 products. Depth: diff 1, minor 3, product 4, sum of
// six 9; |b|² 5; w·M 10; sum of five 14.
template <class NT, class Diff>
inline NT insphere_det(const Point4* const s[5], const Point4& q, Diff diff) {
  NT b[5][4];
  NT w[5];
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 4; ++j) b[i][j] = diff((*s[i])[j], q[j]);
    w[i] = b[i][0] * b[i][0] + b[i][1] * b[i][1] + b[i][2] * b[i][2] + b[i][3] * b[i][3];
  }
  NT xy[5][5], zt[5][5];
  for (int r = 0; r < 5; ++r)
    for (int c = r + 1; c < 5; ++c) {
      xy[r][c] = b[r][0] * b[c][1] - b[r][1] * b[c][0];
      zt[r][c] = b[r][2] * b[c][3] - b[r][3] * b[c][2];
    }
  auto minor4 = [&](int a, int e, int c, int d) {
    return xy[a][e] * zt[c][d] - xy[a][c] * zt[e][d] + xy[a][d] * zt[e][c] + xy[e][c] * zt[a][d] -
           xy[e][d] * zt[a][c] + xy[c][d] * zt[a][e];
  };
  return w[0] * minor4(1, 2, 3, 4) - w[1] * minor4(0, 2, 3, 4) + w[2] * minor4(0, 1, 3, 4) -
         w[3] * minor4(0, 1, 2, 4) + w[4] * minor4(0, 1, 2, 3);
}

// Stage 1, semi-static filters: the determinant in plain double, bounded by the column maxima.
// Every monomial of the expansion takes one entry per column, so the absolute-value expression
// is at most (number of monomials) × Π column maxima; the bound is looser than stage 2's but
// costs a handful of comparisons. Guards: column maxima ≤ 1e30 (no overflow) and a bound
// ≥ 1e-150 (any underflow error, ≤ 1e-170 after amplification, stays far below it).
inline constexpr double kSemiStaticMaxColumn = 1e30;
inline constexpr double kSemiStaticMinBound = 1e-150;
inline constexpr double kOrientSemiCoef = 24 * (kOrientDepth + 8) * DBL_EPSILON / 2;
inline constexpr double kInsphereSemiCoef = 120 * (kInsphereDepth + 8) * DBL_EPSILON / 2;

inline int semi_static_sign(double det, double bound, double max_column) {
  if (!(max_column <= kSemiStaticMaxColumn) || !(bound >= kSemiStaticMinBound)) return kUndecided;
  if (det > bound) return 1;
  if (det < -bound) return -1;
  return kUndecided;
}

inline int insphere_semi_static(const Point4* const s[5], const Point4& q) {
  double mx[4] = {0, 0, 0, 0}, mw = 0;
  for (int i = 0; i < 5; ++i) {
    double w = 0;
    for (int j = 0; j < 4; ++j) {
      const double d = (*s[i])[j] - q[j];
      mx[j] = std::max(mx[j], std::fabs(d));
      w += d * d;
    }
    mw = std::max(mw, w);
  }
  const double det = insphere_det<double>(s, q, [](double x, double y) { return x - y; });
  const double bound = kInsphereSemiCoef * mx[0] * mx[1] * mx[2] * mx[3] * mw * (1 + 1e-12);
  return semi_static_sign(det, bound, std::max(std::max(mx[0], mx[1]), std::max(mx[2], mx[3])));
}

/// insphere4_sos for a call whose stage 1 already failed: runs stages 2 to 4 and the tie-break.
int insphere4_sos_past_semi_static(const Point4* const s[5], const VertexId s_ids[5],
                                   const Point4& q, VertexId q_id);

}  // namespace mesh4d::delaunay::detail
