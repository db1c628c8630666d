#include "delaunay/geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "delaunay/cramer4.h"

namespace mesh4d::delaunay {
namespace {

// Solves A x = b (4×4) by Cramer's rule (cramer4.h): half the time of elimination with
// pivoting. Only an exactly singular A is refused: a nearly flat pentatope has a huge but finite
// circumcenter, which the refinement rules need to see (R2 then inserts its projection on the
// box, which lies in the circumball and so destroys the pentatope).
bool solve4(const double a[4][4], const double b[4], double x[4]) {
  double det;
  cramer4([&](int i, int j) { return a[i][j]; }, b, &det, x);
  return det != 0 && std::isfinite(det);
}

double det4(const double m[4][4]) {
  auto minor2 = [&](int r, int c0, int c1) {
    return m[r][c0] * m[r + 1][c1] - m[r][c1] * m[r + 1][c0];
  };
  return minor2(0, 0, 1) * minor2(2, 2, 3) - minor2(0, 0, 2) * minor2(2, 1, 3) +
         minor2(0, 0, 3) * minor2(2, 1, 2) + minor2(0, 1, 2) * minor2(2, 0, 3) -
         minor2(0, 1, 3) * minor2(2, 0, 2) + minor2(0, 2, 3) * minor2(2, 0, 1);
}

}  // namespace

Point4 circumcenter(const Simplex4& s) {
  // Relative to s[0]: 2 (p_i - p_0) · c' = |p_i - p_0|², c = p_0 + c'. Working relative to a
  // vertex keeps the numbers small where the simplex is far from the origin.
  double a[4][4], b[4], x[4];
  for (int i = 0; i < 4; ++i) {
    double len2 = 0;
    for (int j = 0; j < 4; ++j) {
      a[i][j] = 2 * (s[i + 1][j] - s[0][j]);
      len2 += (s[i + 1][j] - s[0][j]) * (s[i + 1][j] - s[0][j]);
    }
    b[i] = len2;
  }
  if (!solve4(a, b, x)) {
    const double inf = std::numeric_limits<double>::infinity();
    return {inf, inf, inf, inf};
  }
  return {s[0][0] + x[0], s[0][1] + x[1], s[0][2] + x[2], s[0][3] + x[3]};
}

double circumradius(const Simplex4& s) {
  return circumradius(s, circumcenter(s));
}

double circumradius(const Simplex4& s, const Point4& center) {
  if (!std::isfinite(center[0])) return std::numeric_limits<double>::infinity();
  // The mean over the vertices damps the rounding of the solve.
  double r = 0;
  for (const Point4& p : s) r += std::sqrt(squared_distance(center, p));
  return r / 5;
}

double shortest_edge(const Simplex4& s) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 5; ++i)
    for (int j = i + 1; j < 5; ++j) best = std::min(best, squared_distance(s[i], s[j]));
  return std::sqrt(best);
}

double radius_edge_ratio(const Simplex4& s) {
  return circumradius(s) / shortest_edge(s);
}

double signed_volume(const Simplex4& s) {
  double m[4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m[i][j] = s[i + 1][j] - s[0][j];
  return det4(m) / 24;
}

double normalized_volume(const Simplex4& s) {
  return normalized_volume(s, circumradius(s));
}

double normalized_volume(const Simplex4& s, double r) {
  if (!std::isfinite(r) || r == 0) return 0;
  const double r2 = r * r;
  return 384 * std::fabs(signed_volume(s)) / (25 * std::sqrt(5.0) * r2 * r2);
}

}  // namespace mesh4d::delaunay
