#include "delaunay/exact_circumcenter.h"

#include <CGAL/Mpzf.h>

#include <cmath>

#include "delaunay/predicate_kernels.h"

namespace mesh4d::delaunay {

std::optional<Point4> exact_circumcenter(const Point4* const s[5]) {
  // With eᵢ = sᵢ − s₀ the center c solves 2 eᵢ · (c − s₀) = |eᵢ|² (i = 1..4); Cramer's rule,
  // every determinant exact (CGAL::Mpzf is exact on sums and products of doubles).
  CGAL::Mpzf a[4][4], b[4];
  for (int i = 0; i < 4; ++i) {
    b[i] = 0;
    for (int j = 0; j < 4; ++j) {
      const CGAL::Mpzf e = CGAL::Mpzf((*s[i + 1])[j]) - CGAL::Mpzf((*s[0])[j]);
      a[i][j] = 2 * e;
      b[i] = b[i] + e * e;
    }
  }
  const CGAL::Mpzf det = detail::det4(a);
  if (CGAL::sign(det) == CGAL::ZERO) return std::nullopt;
  const double d = CGAL::to_double(det);
  Point4 center;
  for (int j = 0; j < 4; ++j) {
    CGAL::Mpzf m[4][4];
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 4; ++k) m[i][k] = k == j ? b[i] : a[i][k];
    center[j] = (*s[0])[j] + CGAL::to_double(detail::det4(m)) / d;
    if (!std::isfinite(center[j])) return std::nullopt;
  }
  return center;
}

}  // namespace mesh4d::delaunay
