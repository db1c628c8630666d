// Diagonal contacts made face contacts, the last step of the segmentation cleanup
// (segmentation_cleanup.h): two voxels of a label that meet only at an edge or a corner are one
// piece for the label function where it gives the center of their block to their label
// (label_pieces.h), and two pieces otherwise. A mesh follows the label function, so where it
// joins them, a face path between the two inside the block takes the label: then the cleaned
// image's face-connected pieces are the label function's, and the mesh's pieces can be compared
// with either. A voxel changes label only when the face neighbors of its old label stay
// connected around it (within its 3⁴ neighborhood), so no piece of another label splits.
#pragma once

#include <cstddef>
#include <map>

#include "domain/label_image.h"

namespace mesh4d::domain {

struct DiagonalFill {
  struct PerLabel {
    std::size_t contacts = 0;  // diagonal joins made face joins
    std::size_t voxels = 0;    // voxels that took the label
    std::size_t left = 0;      // joins no safe path could make face joins
  };
  std::map<Label, PerLabel> labels;  // the labels with a diagonal join
};

/// Fills the diagonal joins of `image` in place (a few rounds, until none is left or none can be
/// filled).
DiagonalFill fill_diagonal_joins(LabelImage4& image, unsigned threads = 1);

}  // namespace mesh4d::domain
