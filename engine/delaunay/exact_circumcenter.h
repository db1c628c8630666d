// The circumcenter of a pentatope too close to flat for double arithmetic: circumcenter()
// divides by a determinant that rounds to zero (four feature points nearly on one 2-plane of
// voxel-grid coordinates, and a fifth point). The exact orientation is still positive, so the
// pentatope is in the triangulation and needs its ball like any other.
#pragma once

#include <optional>

#include "delaunay/point4.h"

namespace mesh4d::delaunay {

/// The circumcenter from exact determinants, each rounded once to double before the one
/// division: a few units of the last place off. Empty for an exactly flat simplex, or a center
/// beyond the doubles.
std::optional<Point4> exact_circumcenter(const Point4* const s[5]);

}  // namespace mesh4d::delaunay
