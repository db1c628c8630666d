#include "domain/face_components.h"

namespace mesh4d::domain {

FacePieces face_pieces(const LabelImage4& image, bool with_background) {
  const auto& d = image.dims();
  const std::size_t stride[4] = {1, d[0], d[0] * d[1], d[0] * d[1] * d[2]};
  FacePieces out;
  out.piece.assign(image.voxel_count(), FacePieces::kNoPiece);
  std::vector<std::size_t> frontier;
  for (std::size_t seed = 0; seed < image.voxel_count(); ++seed) {
    if (out.piece[seed] != FacePieces::kNoPiece || (!with_background && image.at(seed) == 0))
      continue;
    const auto id = static_cast<std::uint32_t>(out.pieces.size());
    FacePieces::Piece p;
    p.label = image.at(seed);
    out.piece[seed] = id;
    frontier.assign(1, seed);
    while (!frontier.empty()) {
      const std::size_t i = frontier.back();
      frontier.pop_back();
      ++p.voxels;
      // The coordinates once per voxel: the neighbors by strides.
      const std::size_t c[4] = {i % d[0], i / d[0] % d[1], i / stride[2] % d[2], i / stride[3]};
      const auto visit = [&](std::size_t j) {
        if (out.piece[j] == FacePieces::kNoPiece && image.at(j) == p.label) {
          out.piece[j] = id;
          frontier.push_back(j);
        }
      };
      for (int a = 0; a < 4; ++a) {
        p.touches_border |= c[a] == 0 || c[a] + 1 == d[a];
        if (c[a] > 0) visit(i - stride[a]);
        if (c[a] + 1 < d[a]) visit(i + stride[a]);
      }
    }
    out.pieces.push_back(p);
  }
  return out;
}

}  // namespace mesh4d::domain
