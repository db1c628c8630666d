// In-sphere questions decided from circumballs that the triangulation's owner keeps anyway (the
// refiner measures every new pentatope's): a cavity search then reads one ball instead of five
// vertices and a 5×5 determinant. Only answers that rounding cannot change are given; the
// rest, and every tie, go to the exact predicates, so the triangulation is the same.
#pragma once

#include <cstdint>

#include "delaunay/pentatope_store.h"
#include "delaunay/point4.h"

namespace mesh4d::delaunay {

class ConflictFilter {
 public:
  /// For each of cells[0..count): 1 when p lies certainly strictly inside its circumsphere,
  /// -1 certainly strictly outside, 0 when the filter cannot tell (an infinite pentatope, a
  /// flat one, a ball not precise enough).
  virtual void decide(const CellId* cells, int count, const Point4& p,
                      std::int8_t* verdict) const = 0;
  /// Starts the loads of what decide() reads about these pentatopes (soon asked about).
  virtual void prefetch(const CellId* cells, int count) const = 0;

 protected:
  ~ConflictFilter() = default;
};

/// The certain answer from a ball (circumballs4): `center` within `center_error` of the exact
/// circumcenter, `radius` within center_error plus 11 units of its last place of the exact
/// circumradius. Every rounding below is covered with room (a comment per bound).
inline int ball_verdict(const Point4& center, double radius, double center_error, const Point4& p) {
  // |p − center|², within 6 units of the last place.
  double d2 = 0;
  for (int j = 0; j < 4; ++j) {
    const double t = p[j] - center[j];
    d2 += t * t;
  }
  // |p − exact center| is |p − center| ± e, and the exact radius radius ± (e + 9.1u·radius):
  // the answer is certain beyond twice e plus 90u·radius from radius (u = 2⁻⁵³).
  const double slack = 2.01 * center_error + 1e-14 * radius;
  const double outer = radius + slack, inner = radius - slack;
  // The squares' own roundings and d2's: 36u of room.
  if (d2 > outer * outer * (1 + 4e-15)) return -1;
  if (inner > 0 && d2 < inner * inner * (1 - 4e-15)) return 1;
  return 0;
}

}  // namespace mesh4d::delaunay
