// The output of meshing: a 4D mesh of pentatopes tagged with labels, and the boundary
// tetrahedra between labels (or a label and the background), each with its pentatope.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "delaunay/point4.h"

namespace mesh4d::mesh {

using Label = std::uint16_t;

/// What a vertex is (as in the triangulation): box corner/face, feature (on ∂Ω) or free.
enum class VertexKind : std::uint8_t { box = 1, feature = 2, free = 3 };

struct BoundaryTetrahedron {
  std::array<std::uint32_t, 4> vertices;
  std::uint32_t pentatope;  // the output pentatope this facet belongs to
  Label inner;              // that pentatope's label
  Label outer;              // the label across (0: background)
};

struct Mesh4 {
  std::vector<Point4> vertices;
  std::vector<VertexKind> vertex_kinds;  // one per vertex
  std::vector<std::array<std::uint32_t, 5>> pentatopes;
  std::vector<Label> labels;  // one per pentatope, never 0
  std::vector<BoundaryTetrahedron> boundary;
  // Periodic time (docs/mesh-format.md): the pentatopes represent the cycle from period_start
  // to period_start + period, each anchored (its lowest vertex) in that span. One that crosses
  // its end has vertices past it, each glued to the vertex one period earlier:
  // periodic_twins holds {later, earlier} for each. period 0: time is open.
  double period_start = 0;
  double period = 0;
  std::vector<std::array<std::uint32_t, 2>> periodic_twins;
  bool periodic() const { return period > 0; }
};

}  // namespace mesh4d::mesh
