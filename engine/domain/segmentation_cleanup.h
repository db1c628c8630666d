// Segmentation cleanup, said out loud (docs/algorithm.md, "Input and the domain"): automatic
// segmentations carry specks, islands of a label a few voxels large, and holes, small pockets of
// another label or background inside one. A mesh at spacing Δ cannot follow them, and the
// certificate compares the mesh with the image's pieces, so they go before meshing: every
// face-connected piece of fewer than `min_voxels` voxels takes the label most of its face
// neighbors have. Background that reaches the image's border is the outside, never a hole;
// smaller pieces go first, each seeing the labels as the ones before left them. Then the
// diagonal contacts that the label function joins become face contacts (diagonal_fill.h), so
// that the cleaned image's face-connected pieces are the label function's. What changed is
// reported per label, for the job's warnings.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "domain/diagonal_fill.h"
#include "domain/label_image.h"

namespace mesh4d::domain {

/// The default threshold, in voxels: a piece below it spans under about 3 voxels along each
/// of the four axes (3⁴ = 81).
constexpr std::size_t kDefaultMinIslandVoxels = 81;

struct CleanupReport {
  struct PerLabel {
    Label label = 0;
    std::size_t pieces = 0;  // islands of this label removed (label 0: holes filled)
    std::size_t voxels = 0;
  };
  std::vector<PerLabel> labels;  // labels that lost a piece, ascending
  DiagonalFill diagonal;         // the diagonal joins made face joins
  /// One sentence per label, for the job's warnings; none when nothing was removed.
  std::vector<std::string> warnings(std::size_t min_voxels) const;
};

/// Removes the pieces below `min_voxels` in place, then fills the diagonal joins (0: nothing is
/// done). The pieces are found on up to `threads` threads (the same cleanup with any number).
CleanupReport clean_segmentation(LabelImage4& image, std::size_t min_voxels, unsigned threads = 1);

}  // namespace mesh4d::domain
