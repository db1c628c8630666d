// What the image says each label should be, for comparing a mesh with it
// (mesh/topology_certificate.h counts the mesh's side): per label, its pieces as the label
// function joins them (label_pieces.h) and its face-connected pieces (voxels that share a 3D
// face, eight neighbors in 4D), its voxels and their 4-volume, and per frame its 3D volume.
#pragma once

#include <cstddef>
#include <map>
#include <vector>

#include "domain/label_image.h"

namespace mesh4d::domain {

struct LabelCensus {
  struct PerLabel {
    Label label = 0;
    std::size_t voxels = 0;
    std::size_t components = 0;       // pieces of the label function (label_pieces.h)
    std::size_t face_components = 0;  // face-connected pieces
    double volume = 0;                // voxels × the product of the spacings
  };
  std::vector<PerLabel> labels;  // the non-zero labels, ascending
  /// Each frame's time (its voxel centers' t) and each label's 3D volume in it (voxels × the
  /// spatial spacings); frames without foreground are listed with no volumes.
  std::vector<double> frame_times;
  std::vector<std::map<Label, double>> frame_volumes;
};

/// The pieces are found on up to `threads` threads (the same census with any number).
LabelCensus take_census(const LabelImage4& image, unsigned threads = 1);

/// The census of a cycle in periodic time (periodic_time.h): pieces are counted with its last
/// frame next to its first.
LabelCensus take_periodic_census(const LabelImage4& cycle, unsigned threads = 1);

}  // namespace mesh4d::domain
