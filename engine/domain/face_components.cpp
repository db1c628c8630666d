#include "domain/face_components.h"

#include <limits>

namespace mesh4d::domain {

FacePieces face_pieces(const LabelImage4& image) {
  const auto& d = image.dims();
  const std::size_t n = image.voxel_count();
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  FacePieces out;
  out.piece.assign(n, kNone);
  std::vector<std::size_t> frontier;
  const auto on_border = [&](std::size_t i) {
    const std::size_t c[4] = {i % d[0], i / d[0] % d[1], i / (d[0] * d[1]) % d[2],
                              i / (d[0] * d[1] * d[2])};
    for (int a = 0; a < 4; ++a)
      if (c[a] == 0 || c[a] + 1 == d[a]) return true;
    return false;
  };
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (out.piece[seed] != kNone) continue;
    const auto id = static_cast<std::uint32_t>(out.pieces.size());
    FacePieces::Piece p;
    p.label = image.at(seed);
    out.piece[seed] = id;
    frontier.assign(1, seed);
    while (!frontier.empty()) {
      const std::size_t i = frontier.back();
      frontier.pop_back();
      ++p.voxels;
      p.touches_border |= on_border(i);
      for_each_face_neighbor(image, i, [&](std::size_t j) {
        if (out.piece[j] == kNone && image.at(j) == p.label) {
          out.piece[j] = id;
          frontier.push_back(j);
        }
      });
    }
    out.pieces.push_back(p);
  }
  return out;
}

}  // namespace mesh4d::domain
