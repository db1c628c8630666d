#include "delaunay/circumballs.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "delaunay/cramer4.h"

namespace mesh4d::delaunay {
namespace {

constexpr int kLanes = 4;

// Structure of arrays, lane last, so that each statement below is one vector operation. The
// expressions are those of geometry.cpp (solve4, circumcenter, circumradius, shortest_edge):
// change both together.
[[gnu::always_inline]] inline void measure(const Point4* const vertices[kLanes][5],
                                           Circumball out[kLanes]) {
  double p[5][4][kLanes];
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 4; ++j)
      for (int l = 0; l < kLanes; ++l) p[k][j][l] = (*vertices[l][k])[j];
  // Relative to vertex 0: 2 (p_i - p_0) · c' = |p_i - p_0|².
  double a[4][4][kLanes], b[4][kLanes];
  for (int i = 0; i < 4; ++i) {
    for (int l = 0; l < kLanes; ++l) b[i][l] = 0;
    for (int j = 0; j < 4; ++j)
      for (int l = 0; l < kLanes; ++l) {
        a[i][j][l] = 2 * (p[i + 1][j][l] - p[0][j][l]);
        b[i][l] += (p[i + 1][j][l] - p[0][j][l]) * (p[i + 1][j][l] - p[0][j][l]);
      }
  }
  // Cramer's rule, as solve4.
  double x[4][kLanes], det[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    const double bl[4] = {b[0][l], b[1][l], b[2][l], b[3][l]};
    double xl[4];
    // The flat lanes (det 0 or not finite) are replaced at the end.
    cramer4([&](int i, int j) { return a[i][j][l]; }, bl, &det[l], xl);
    for (int i = 0; i < 4; ++i) x[i][l] = xl[i];
  }
  double c[4][kLanes];
  for (int j = 0; j < 4; ++j)
    for (int l = 0; l < kLanes; ++l) c[j][l] = p[0][j][l] + x[j][l];
  // circumradius: the mean distance to the vertices, summed in vertex order.
  double r[kLanes] = {};
  for (int k = 0; k < 5; ++k) {
    double d2[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      double q = 0;
      for (int j = 0; j < 4; ++j) q += (c[j][l] - p[k][j][l]) * (c[j][l] - p[k][j][l]);
      d2[l] = q;
    }
    for (int l = 0; l < kLanes; ++l) r[l] += std::sqrt(d2[l]);
  }
  double e2[kLanes];
  for (int l = 0; l < kLanes; ++l) e2[l] = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 5; ++i)
    for (int k = i + 1; k < 5; ++k)
      for (int l = 0; l < kLanes; ++l) {
        double q = 0;
        for (int j = 0; j < 4; ++j) q += (p[i][j][l] - p[k][j][l]) * (p[i][j][l] - p[k][j][l]);
        e2[l] = std::min(e2[l], q);
      }
  // The center's error bound (forward error analysis, u = 2⁻⁵³): the entries of A carry one
  // rounding, those of b at most six; each of the 24 terms of det(A) takes at most 14 roundings
  // in all (4 in its entries, 10 in the arithmetic), each of the 24 terms of a numerator (three
  // entries of A and one of b) at most 18.
  // So |det − exact| ≤ eD = 15u·1.01·24·BA⁴ and |numerator − exact| ≤ eN = 18u·1.01·24·BA³·Bb
  // (BA, Bb: the largest |entry| of A and of b), and the solution's coordinate j is off by at
  // most (|x_j|·eD + eN)/(|det| − eD) plus its division's and the center's sum's roundings.
  // Over four coordinates, twice the largest. Constants rounded up. Entries below 1e-50 could
  // take products into the subnormal range, where roundings are no longer relative: no bound
  // there (never on images in millimeters).
  constexpr double u = 0x1p-53;
  double err[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    double ba = 0, bb = 0, xm = 0, cm = 0;
    for (int i = 0; i < 4; ++i) {
      bb = std::max(bb, b[i][l]);
      for (int j = 0; j < 4; ++j) ba = std::max(ba, std::abs(a[i][j][l]));
    }
    for (int j = 0; j < 4; ++j) {
      xm = std::max(xm, std::abs(x[j][l]));
      cm = std::max(cm, std::abs(c[j][l]));
    }
    const double ba2 = ba * ba;
    const double e_det = 364 * u * (ba2 * ba2), e_num = 437 * u * (ba2 * ba * bb);
    const double margin = std::abs(det[l]) - e_det;
    err[l] = 2 * ((xm * e_det + e_num) / margin * (1 + 1e-10) + 4 * u * xm + 2 * u * cm);
    if (!(ba >= 1e-50)) err[l] = std::numeric_limits<double>::infinity();
  }
  const double inf = std::numeric_limits<double>::infinity();
  for (int l = 0; l < kLanes; ++l) {
    out[l].center_error = err[l] >= 0 && err[l] < inf ? err[l] : inf;
    if (det[l] == 0 || !std::isfinite(det[l])) {
      out[l].center_error = inf;
      out[l].center = {inf, inf, inf, inf};
      out[l].radius = inf;
    } else {
      for (int j = 0; j < 4; ++j) out[l].center[j] = c[j][l];
      out[l].radius = std::isfinite(out[l].center[0]) ? r[l] / 5 : inf;
    }
    out[l].shortest_edge = std::sqrt(e2[l]);
  }
}

void measure_default(const Point4* const vertices[kLanes][5], Circumball out[kLanes]) {
  measure(vertices, out);
}

#if defined(__x86_64__) && defined(__GNUC__)
// The same code with 256-bit vectors; no FMA, which would change the roundings.
[[gnu::target("avx2,no-fma")]] void measure_avx2(const Point4* const vertices[kLanes][5],
                                                 Circumball out[kLanes]) {
  measure(vertices, out);
}
#endif

}  // namespace

void circumballs4(const Point4* const vertices[4][5], Circumball out[4], bool portable) {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2 && !portable) return measure_avx2(vertices, out);
#endif
  measure_default(vertices, out);
}

}  // namespace mesh4d::delaunay
