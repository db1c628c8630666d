// Double-double ("double-word") arithmetic: a value hi + lo with |lo| ≤ ulp(hi)/2, about 106
// bits of precision. The predicates use it as a third filter stage: near-degenerate input (a
// jittered grid, points nearly co-spherical) defeats the double filters but rarely needs more
// than twice the precision, and this is some ten times cheaper than multiprecision.
//
// Error model (Joldes, Muller, Popescu, "Tight and rigorous error bounds for basic building
// blocks of double-word arithmetic", ACM TOMS 2017): the accurate addition below has relative
// error ≤ 3u² + 13u³ and the product ≤ 7u² (u = 2⁻⁵³), without underflow or overflow. The
// predicates use the blanket bound kRelativeError = 16u² per operation.
#pragma once

#include <cfloat>

namespace mesh4d::delaunay {

struct DoubleDouble {
  double hi = 0;
  double lo = 0;

  static constexpr double kUnit = DBL_EPSILON / 2;
  static constexpr double kRelativeError = 16 * kUnit * kUnit;

  static DoubleDouble two_sum(double a, double b) {
    const double s = a + b;
    const double bb = s - a;
    return {s, (a - (s - bb)) + (b - bb)};
  }
  static DoubleDouble fast_two_sum(double a, double b) {  // needs |a| ≥ |b| or a == 0
    const double s = a + b;
    return {s, b - (s - a)};
  }
  // Dekker's product: exact a·b as hi + lo, with Veltkamp's split (no FMA on baseline x86-64).
  static DoubleDouble two_prod(double a, double b) {
    constexpr double kSplitter = 134217729.0;  // 2^27 + 1
    const double p = a * b;
    const double ca = kSplitter * a, cb = kSplitter * b;
    const double ah = ca - (ca - a), al = a - ah;
    const double bh = cb - (cb - b), bl = b - bh;
    return {p, ((ah * bh - p) + ah * bl + al * bh) + al * bl};
  }
};

inline DoubleDouble operator+(const DoubleDouble& x, const DoubleDouble& y) {
  DoubleDouble s = DoubleDouble::two_sum(x.hi, y.hi);
  const DoubleDouble t = DoubleDouble::two_sum(x.lo, y.lo);
  s = DoubleDouble::fast_two_sum(s.hi, s.lo + t.hi);
  return DoubleDouble::fast_two_sum(s.hi, s.lo + t.lo);
}

inline DoubleDouble operator-(const DoubleDouble& x, const DoubleDouble& y) {
  return x + DoubleDouble{-y.hi, -y.lo};
}

inline DoubleDouble operator*(const DoubleDouble& x, const DoubleDouble& y) {
  DoubleDouble p = DoubleDouble::two_prod(x.hi, y.hi);
  const double cross = x.hi * y.lo + x.lo * y.hi;
  return DoubleDouble::fast_two_sum(p.hi, p.lo + cross);
}

}  // namespace mesh4d::delaunay
