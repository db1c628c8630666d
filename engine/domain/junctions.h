// Triple junctions of a multi-label image: where three labels meet (the ventricle's pool, wall
// and background), ∂Ω is not a manifold but three sheets joined along a 2D junction. The
// refiner samples the junction before anything else, as Mesh_3 protects 1D features in 3D:
// sheets restricted to a Delaunay triangulation that samples their junction meet along it
// instead of pinching around it.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <vector>

#include "domain/surface_oracle.h"

namespace mesh4d::domain {

struct JunctionPoint {
  Point4 point;                 // I_a = I_b = I_c there, to ~1e-12, and no other label larger
  std::array<Label, 3> labels;  // ascending
};

/// The point of the junction of labels a, b, c nearest (in Newton's sense) to `seed`: solves
/// I_a − I_b = I_b − I_c = 0 by minimum-norm Newton steps. Nothing when it does not converge
/// within a voxel-cell diagonal of the seed, or when a fourth label wins there.
std::optional<Point4> project_to_junction(const SurfaceOracle& oracle, const Point4& seed, Label a,
                                          Label b, Label c);

/// Points of every triple junction, thinned greedily in scan order: one seed per voxel cell whose
/// 16 corners hold three or more labels (the three most frequent), skipped unless
/// `far_enough(seed)`, projected, kept when `far_enough(point)`, and then passed to `taken` (so
/// the caller's spatial index sees it before the next query).
std::vector<JunctionPoint> sample_junctions(const SurfaceOracle& oracle,
                                            const std::function<bool(const Point4&)>& far_enough,
                                            const std::function<void(const Point4&)>& taken);

}  // namespace mesh4d::domain
