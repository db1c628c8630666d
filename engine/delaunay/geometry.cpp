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

double det3(const double a[3], const double b[3], const double c[3]) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
         a[2] * (b[0] * c[1] - b[1] * c[0]);
}

double dot4(const double a[4], const double b[4]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
}

void facet_edges(const Tetrahedron4& f, double e[3][4]) {
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 4; ++k) e[r][k] = f[r + 1][k] - f[0][k];
}

}  // namespace

Point4 hyperplane_normal(const Tetrahedron4& f) {
  // Cofactor expansion of det[e₁; e₂; e₃; u] along its last row: n_k = (−1)^(3+k) · the minor
  // without column k.
  double e[3][4];
  facet_edges(f, e);
  Point4 n;
  for (int k = 0; k < 4; ++k) {
    int c[3], m = 0;
    for (int j = 0; j < 4; ++j)
      if (j != k) c[m++] = j;
    double rows[3][3];
    for (int r = 0; r < 3; ++r)
      for (int j = 0; j < 3; ++j) rows[r][j] = e[r][c[j]];
    const double minor = det3(rows[0], rows[1], rows[2]);
    n[k] = (3 + k) % 2 == 0 ? minor : -minor;
  }
  return n;
}

Point4 facet_circumcenter(const Tetrahedron4& f) {
  // f₀ + Σ x_r e_r with e_r · (c − f₀) = |e_r|²/2: the Gram system, by Cramer's rule.
  double e[3][4];
  facet_edges(f, e);
  double g[3][3], b[3];
  for (int r = 0; r < 3; ++r) {
    for (int s = 0; s < 3; ++s) g[r][s] = dot4(e[r], e[s]);
    b[r] = 0.5 * g[r][r];
  }
  const double det = det3(g[0], g[1], g[2]);
  double x[3];
  for (int r = 0; r < 3; ++r) {
    double m[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m[i][j] = j == r ? b[i] : g[i][j];
    x[r] = det3(m[0], m[1], m[2]) / det;
  }
  Point4 c;
  for (int k = 0; k < 4; ++k) c[k] = f[0][k] + x[0] * e[0][k] + x[1] * e[1][k] + x[2] * e[2][k];
  return c;
}

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
