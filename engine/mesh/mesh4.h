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
};

}  // namespace mesh4d::mesh
