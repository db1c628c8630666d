// Points of 4D space-time (x, y, z, t) in physical units, and vertex ids.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

namespace mesh4d {

/// A point of R⁴: x, y, z in the image's length unit, t scaled by the time scale.
using Point4 = std::array<double, 4>;

/// Index of a vertex in a triangulation. Ids also order vertices by age (smaller is older),
/// which the symbolic tie-break of the in-sphere predicate relies on.
using VertexId = std::uint32_t;

/// Squared Euclidean distance.
inline double squared_distance(const Point4& a, const Point4& b) {
  double d = 0;
  for (int i = 0; i < 4; ++i) d += (a[i] - b[i]) * (a[i] - b[i]);
  return d;
}

/// Euclidean distance (the refiner, the oracle and the checks all measure with this one).
inline double distance(const Point4& a, const Point4& b) {
  return std::sqrt(squared_distance(a, b));
}

}  // namespace mesh4d
