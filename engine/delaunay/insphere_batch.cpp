#include "delaunay/insphere_batch.h"

#include <algorithm>
#include <cmath>

#include "delaunay/predicate_kernels.h"

namespace mesh4d::delaunay::detail {
namespace {

constexpr int kLanes = 4;

// Structure of arrays, lane last, so that each statement is one vector operation. The
// expressions are insphere_det's and insphere_semi_static's (predicate_kernels.h): change them
// together.
[[gnu::always_inline]] inline void filter(const Point4* const vertices[kLanes][5], const Point4& q,
                                          int out[kLanes]) {
  double b[5][4][kLanes], w[5][kLanes];
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j)
      for (int l = 0; l < kLanes; ++l) b[i][j][l] = (*vertices[l][i])[j] - q[j];
  for (int i = 0; i < 5; ++i)
    for (int l = 0; l < kLanes; ++l)
      w[i][l] = b[i][0][l] * b[i][0][l] + b[i][1][l] * b[i][1][l] + b[i][2][l] * b[i][2][l] +
                b[i][3][l] * b[i][3][l];
  // The bound's column maxima and largest lifted entry, in vertex order.
  double mx[4][kLanes] = {}, mw[kLanes] = {};
  for (int i = 0; i < 5; ++i)
    for (int l = 0; l < kLanes; ++l) {
      for (int j = 0; j < 4; ++j) mx[j][l] = std::max(mx[j][l], std::fabs(b[i][j][l]));
      mw[l] = std::max(mw[l], w[i][l]);
    }
  double xy[5][5][kLanes], zt[5][5][kLanes];
  for (int r = 0; r < 5; ++r)
    for (int c = r + 1; c < 5; ++c)
      for (int l = 0; l < kLanes; ++l) {
        xy[r][c][l] = b[r][0][l] * b[c][1][l] - b[r][1][l] * b[c][0][l];
        zt[r][c][l] = b[r][2][l] * b[c][3][l] - b[r][3][l] * b[c][2][l];
      }
  double det[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    const auto minor4 = [&](int a, int e, int c, int d) {
      return xy[a][e][l] * zt[c][d][l] - xy[a][c][l] * zt[e][d][l] + xy[a][d][l] * zt[e][c][l] +
             xy[e][c][l] * zt[a][d][l] - xy[e][d][l] * zt[a][c][l] + xy[c][d][l] * zt[a][e][l];
    };
    det[l] = w[0][l] * minor4(1, 2, 3, 4) - w[1][l] * minor4(0, 2, 3, 4) +
             w[2][l] * minor4(0, 1, 3, 4) - w[3][l] * minor4(0, 1, 2, 4) +
             w[4][l] * minor4(0, 1, 2, 3);
  }
  for (int l = 0; l < kLanes; ++l) {
    const double bound =
        kInsphereSemiCoef * mx[0][l] * mx[1][l] * mx[2][l] * mx[3][l] * mw[l] * (1 + 1e-12);
    out[l] = semi_static_sign(det[l], bound,
                              std::max(std::max(mx[0][l], mx[1][l]), std::max(mx[2][l], mx[3][l])));
  }
}

void filter_default(const Point4* const vertices[kLanes][5], const Point4& q, int out[kLanes]) {
  filter(vertices, q, out);
}

#if defined(__x86_64__) && defined(__GNUC__)
// The same code with 256-bit vectors; no FMA, which would change the roundings.
[[gnu::target("avx2,no-fma")]] void filter_avx2(const Point4* const vertices[kLanes][5],
                                                const Point4& q, int out[kLanes]) {
  filter(vertices, q, out);
}
#endif

}  // namespace

void insphere_semi_static4(const Point4* const vertices[4][5], const Point4& q, int out[4],
                           bool portable) {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2 && !portable) return filter_avx2(vertices, q, out);
#endif
  filter_default(vertices, q, out);
}

}  // namespace mesh4d::delaunay::detail
