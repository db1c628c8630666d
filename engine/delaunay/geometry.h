// Measures of a pentatope in double precision (docs/algorithm.md, "Measures"). These decide
// quality, not topology, so they need robustness (pivoting, no catastrophic formulas), not
// exactness.
#pragma once

#include <array>

#include "delaunay/point4.h"

namespace mesh4d::delaunay {

using Simplex4 = std::array<Point4, 5>;
/// A pentatope's facet: four points spanning a hyperplane of R⁴.
using Tetrahedron4 = std::array<Point4, 4>;

/// Center of the 3-sphere through the five vertices. For a flat simplex (no unique sphere) every
/// coordinate is infinite.
Point4 circumcenter(const Simplex4& s);

/// Distance from the circumcenter to the vertices (infinite for a flat simplex).
double circumradius(const Simplex4& s);
/// The same from a circumcenter already computed (the same result as circumradius(s)).
double circumradius(const Simplex4& s, const Point4& center);

/// Length of the shortest of the ten edges.
double shortest_edge(const Simplex4& s);

/// Circumradius over shortest edge. The regular pentatope has the smallest value, √(2/5) ≈ 0.632.
double radius_edge_ratio(const Simplex4& s);

/// Signed 4-volume: det[p1-p0, p2-p0, p3-p0, p4-p0] / 24.
double signed_volume(const Simplex4& s);

/// Volume over the volume of the regular pentatope with the same circumradius,
/// 384·|V| / (25·√5·R⁴): 1 for the regular pentatope, 0 for a flat one.
double normalized_volume(const Simplex4& s);
/// The same from a circumradius already computed (circumradius(s), for the same result).
double normalized_volume(const Simplex4& s, double circumradius);

/// Normal of the facet's hyperplane: the 4D cross product n of the edges eᵢ = pᵢ − p₀, so that
/// det[e₁; e₂; e₃; u − p₀] = n · (u − p₀). |n| is six times the facet's 3-volume.
Point4 hyperplane_normal(const Tetrahedron4& f);

/// Center of the facet's circumsphere within its own hyperplane. For a flat facet the
/// coordinates are not finite.
Point4 facet_circumcenter(const Tetrahedron4& f);

}  // namespace mesh4d::delaunay
