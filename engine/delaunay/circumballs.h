// The circumballs and shortest edges of pentatopes four at a time: what the refiner measures on
// every pentatope an insertion makes (some 120 of them; 15 % of a refinement's time, scalar).
//
// Each lane does exactly the arithmetic of circumcenter(), circumradius(s, center) and
// shortest_edge() in geometry.cpp, in the same order, without fused multiply-adds: the results
// are bitwise the same (a test compares them), so meshes do not depend on which is used. Where
// the processor has AVX2, four lanes share each instruction; elsewhere two.
#pragma once

#include "delaunay/point4.h"

namespace mesh4d::delaunay {

struct Circumball {
  Point4 center;  // every coordinate infinite for a flat pentatope, as circumcenter()
  double radius;  // circumradius(s, center)
  double shortest_edge;
  /// A bound on the distance from `center` to the exact circumcenter, from the roundings of
  /// the arithmetic above (infinite for a flat pentatope, or one too close to flat for the
  /// bound to hold); |radius − exact circumradius| is within it plus 11 units of the last
  /// place of radius. What lets an in-sphere question be decided from the ball alone
  /// (conflict_filter.h).
  double center_error;
};

/// vertices[l][k]: vertex k of pentatope l. With `portable`, the code for processors without
/// AVX2 even where it has it (tests compare both).
void circumballs4(const Point4* const vertices[4][5], Circumball out[4], bool portable = false);

}  // namespace mesh4d::delaunay
