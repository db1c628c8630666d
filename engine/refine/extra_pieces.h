// What ManifoldRelabeling::remove_extra_pieces() (extra_pieces.cpp) did. Pieces the image does
// not have (docs/refinement.md, "Closed, manifold region boundaries where
// labels meet"): where a region thins, the refinement can cut off a small piece of it that
// touches nothing of its label, though the image joins it to another piece. Such a piece takes
// its neighbors' label. Whether the image joins two pieces is found in the image itself: from
// the voxels of the piece's circumcenters, a walk through the voxels the label function joins
// (domain/label_pieces.h) that reaches a voxel holding another piece's circumcenter. Run after
// the manifold step; a
// piece whose move would put a facet more than Δ/2 from ∂Ω, or a pentatope that may not move,
// or make a link fail, stays; so do a label's largest piece and pieces of more than 64
// pentatopes.
#pragma once

#include <cstddef>

namespace mesh4d::refine {

struct ExtraPieces {
  std::size_t found = 0;         // pieces that share an image piece with a larger one
  std::size_t removed = 0;       // of those, given their neighbors' label
  std::size_t moved = 0;         // pentatopes that changed label
  std::size_t links_mended = 0;  // failing (vertex, label) links the moves mended
};

}  // namespace mesh4d::refine
