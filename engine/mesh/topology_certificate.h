// The topology certificate of an output mesh (docs/algorithm.md, "Output"), computed the way an
// outside verifier would: from the pentatopes and their labels alone, not from what the refiner
// believes. For each label:
// - its region's facet-connected pieces (two pentatopes are connected when they share a
//   tetrahedral facet), and how many of them meet another piece of the label only at a vertex,
//   an edge or a triangle;
// - its region's boundary (the facets of its pentatopes that no other pentatope of the label
//   shares): the triangles not in exactly two boundary facets, the boundary edges whose link is
//   not a circle, and the boundary vertices whose link is not a 2-sphere (a closed 3-manifold
//   boundary has none);
// - the boundary facets that the mesh's own boundary list lacks or adds;
// - the region's 4-volume.
#pragma once

#include <cstddef>
#include <vector>

#include "mesh/mesh4.h"

namespace mesh4d::mesh {

struct LabelTopology {
  Label label = 0;
  std::size_t pentatopes = 0;
  std::size_t components = 0;           // facet-connected pieces of the region
  std::size_t touching_components = 0;  // pieces that meet another piece at a lower face only
  std::size_t boundary_facets = 0;
  std::size_t non_manifold_triangles = 0;    // in other than two of the region's boundary facets
  std::size_t non_manifold_edges = 0;        // boundary edges whose link is not one circle
  std::size_t non_manifold_vertices = 0;     // boundary vertices whose link is not a 2-sphere
  std::size_t boundary_list_mismatches = 0;  // facets in the computed boundary xor Mesh4::boundary
  double volume = 0;                         // 4-volume, physical units⁴
};

struct TopologyCertificate {
  std::vector<LabelTopology> labels;  // by label, ascending
  /// Every region's boundary a closed 3-manifold, and the mesh's boundary list the true one.
  bool manifold() const;
};

/// Certifies `mesh` (any number of pentatopes; no check of geometry beyond the volumes); a mesh
/// in periodic time as the glued cycle (periodic_mesh.h). Its sorts and link checks run on up to
/// `threads` threads (the same certificate with any number).
TopologyCertificate certify_topology(const Mesh4& mesh, unsigned threads = 1);

}  // namespace mesh4d::mesh
