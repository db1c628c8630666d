// How far the output boundary strays from ∂Ω: the oracle's closest surface point of sampled
// boundary points (the centroids of boundary tetrahedra, whose vertices lie on ∂Ω, are where a
// flat facet is farthest from a curved surface). Tests hold the refiner to a bound with it and
// the quality report carries it.
#pragma once

#include <cstddef>

#include "domain/surface_oracle.h"
#include "mesh/mesh4.h"

namespace mesh4d::refine {

struct BoundaryDistance {
  std::size_t samples = 0;
  double max = 0;   // physical units
  double mean = 0;  // physical units
};

/// Samples at most `max_samples` boundary tetrahedra, evenly spread over the list.
BoundaryDistance measure_boundary_distance(const mesh::Mesh4& mesh,
                                           const domain::SurfaceOracle& oracle,
                                           std::size_t max_samples = 2000);

}  // namespace mesh4d::refine
