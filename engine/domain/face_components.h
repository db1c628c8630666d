// The face-connected pieces of every label of an image (voxels that share a 3D face: eight
// neighbors in 4D), the connectivity the image's topology is stated in (label_census.h) and the
// cleanup works on (segmentation_cleanup.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "domain/label_image.h"

namespace mesh4d::domain {

struct FacePieces {
  static constexpr std::uint32_t kNoPiece = 0xffffffffu;
  struct Piece {
    Label label = 0;
    std::size_t voxels = 0;
    bool touches_border = false;  // has a voxel on the image's outer layer
  };
  std::vector<Piece> pieces;         // in the order of their first voxel
  std::vector<std::uint32_t> piece;  // by voxel: its piece's index
};

/// `with_background` false: only the non-zero labels' pieces (background voxels: kNoPiece). On
/// up to `threads` threads (slabs of frames flooded side by side, then joined): the same pieces
/// in the same order with any number.
FacePieces face_pieces(const LabelImage4& image, bool with_background = true, unsigned threads = 1);

/// Calls fn(j) for each face neighbor j of voxel i inside the image.
template <class Fn>
void for_each_face_neighbor(const LabelImage4& image, std::size_t i, Fn&& fn) {
  const auto& d = image.dims();
  const std::size_t stride[4] = {1, d[0], d[0] * d[1], d[0] * d[1] * d[2]};
  const std::size_t c[4] = {i % d[0], i / d[0] % d[1], i / (d[0] * d[1]) % d[2],
                            i / (d[0] * d[1] * d[2])};
  for (int a = 0; a < 4; ++a) {
    if (c[a] > 0) fn(i - stride[a]);
    if (c[a] + 1 < d[a]) fn(i + stride[a]);
  }
}

}  // namespace mesh4d::domain
