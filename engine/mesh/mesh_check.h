// Combinatorial fidelity checks of an output mesh's boundary (tests and benchmarks call them):
// whether every label's region is closed, where it pinches, and whether every boundary vertex is
// a feature vertex. Whether those vertices lie on ∂Ω needs the image: see the refiner's tests.
#pragma once

#include <cstddef>

#include "mesh/mesh4.h"

namespace mesh4d::mesh {

struct BoundaryCheck {
  std::size_t triangles = 0;         // distinct (region label, boundary triangle) pairs
  std::size_t odd = 0;               // in an odd number of the region's facets: not closed
  std::size_t pinched = 0;           // in 4 or more: closed but not a manifold there
  std::size_t non_feature_uses = 0;  // boundary-tetrahedron vertex uses not of feature vertices
};

/// Each label's region is bounded by the boundary tetrahedra seen from it (inner == label); a
/// closed 3-manifold holds each of its triangles in exactly two of them.
BoundaryCheck check_boundary(const Mesh4& mesh);

}  // namespace mesh4d::mesh
