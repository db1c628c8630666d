// How far a label's mesh boundary and its boundary in the image lie from each other, both ways,
// sampled: from the mesh (centroids of the boundary tetrahedra with the label on one side) to the
// nearest voxel face between the label and another, and from the image (centres of those faces)
// to the nearest such tetrahedron. ∂Ω is the voxels' own boundary (the label function is the
// nearest voxel's label), so these are distances to the staircase the refiner samples.
#pragma once

#include <cstddef>
#include <vector>

#include "domain/label_image.h"
#include "mesh/mesh4.h"
#include "refine/boundary_distance.h"

namespace mesh4d::refine {

/// One side's samples, max and mean: the same summary as the oracle-based measure.
using SidedDistance = BoundaryDistance;

struct TwoSidedDistance {
  domain::Label label = 0;
  SidedDistance mesh_to_image;  // from boundary tetrahedra to the label's voxel faces
  SidedDistance image_to_mesh;  // from the label's voxel faces to boundary tetrahedra
};

/// One entry per label of the image or the mesh boundary (ascending), each side sampled at most
/// `max_samples` times, evenly over its tetrahedra or faces. A side with nothing to measure
/// against (a label that the mesh lacks, say) keeps its samples at 0. For a mesh in periodic time
/// `image` is the cycle (not closed), its last frame next to its first. The samples' distances
/// are taken on up to `threads` threads (the same figures with any number).
std::vector<TwoSidedDistance> two_sided_distances(const mesh::Mesh4& mesh,
                                                  const domain::LabelImage4& image,
                                                  std::size_t max_samples = 1000,
                                                  unsigned threads = 1);

}  // namespace mesh4d::refine
