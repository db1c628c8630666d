// Points of 4D space-time (x, y, z, t) in physical units, and vertex ids.
#pragma once

#include <array>
#include <cstdint>

namespace mesh4d {

/// A point of R⁴: x, y, z in the image's length unit, t scaled by the time scale.
using Point4 = std::array<double, 4>;

/// Index of a vertex in a triangulation. Ids also order vertices by age (smaller is older),
/// which the symbolic tie-break of the in-sphere predicate relies on.
using VertexId = std::uint32_t;

}  // namespace mesh4d
