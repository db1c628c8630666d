#include "domain/label_census.h"

#include "domain/label_pieces.h"
#include "domain/periodic_time.h"
#include "support/union_find.h"

namespace mesh4d::domain {

namespace {

LabelCensus census_of(const LabelImage4& image, bool periodic, unsigned threads) {
  const auto& d = image.dims();
  const auto& s = image.spacing();
  const double voxel3 = s[0] * s[1] * s[2];
  LabelCensus census;
  std::map<Label, LabelCensus::PerLabel> by_label;
  census.frame_volumes.resize(d[3]);
  for (std::size_t t = 0; t < d[3]; ++t)
    census.frame_times.push_back(image.voxel_center(0, 0, 0, t)[3]);

  for (std::size_t t = 0, i = 0; t < d[3]; ++t)
    for (std::size_t k = 0; k < d[0] * d[1] * d[2]; ++k, ++i) {
      const Label l = image.at(i);
      if (l == 0) continue;
      LabelCensus::PerLabel& per = by_label[l];
      per.label = l;
      ++per.voxels;
      census.frame_volumes[t][l] += voxel3;
    }
  if (!periodic) {
    std::vector<FacePieces::Piece> face;
    for (const FacePieces::Piece& p : label_function_pieces(image, &face, threads).pieces)
      ++by_label[p.label].components;
    for (const FacePieces::Piece& p : face) ++by_label[p.label].face_components;
  } else {
    // The pieces of the cycle tiled three times, each joined with its translates by a period:
    // a path of the glued cycle crosses the seam once per period, and each of its stretches
    // has a translate within the tiled copies (where the seams between copies are the glued
    // cycle's own), so the classes are the glued cycle's pieces.
    const LabelImage4 tiled = tile_cycle(image);
    const std::size_t n = image.voxel_count();
    const auto count = [&](const FacePieces& pieces, std::size_t LabelCensus::PerLabel::*field) {
      support::UnionFind classes(pieces.pieces.size());
      std::vector<std::uint8_t> in_middle(pieces.pieces.size(), 0);
      for (std::size_t i = n; i < 2 * n; ++i) {
        const std::uint32_t p = pieces.piece[i];
        if (p == FacePieces::kNoPiece) continue;
        in_middle[p] = 1;
        for (std::size_t j : {i - n, i + n})
          if (pieces.piece[j] != FacePieces::kNoPiece) classes.join(p, pieces.piece[j]);
      }
      std::vector<std::uint8_t> counted(pieces.pieces.size(), 0);
      for (std::size_t p = 0; p < pieces.pieces.size(); ++p)
        if (in_middle[p] && !counted[classes.find(p)]++)
          ++(by_label[pieces.pieces[p].label].*field);
    };
    count(label_function_pieces(tiled, nullptr, threads), &LabelCensus::PerLabel::components);
    count(face_pieces(tiled, false, threads), &LabelCensus::PerLabel::face_components);
  }
  for (auto& [l, per] : by_label) {
    per.volume = static_cast<double>(per.voxels) * voxel3 * s[3];
    census.labels.push_back(per);
  }
  return census;
}

}  // namespace

LabelCensus take_census(const LabelImage4& image, unsigned threads) {
  return census_of(image, false, threads);
}

LabelCensus take_periodic_census(const LabelImage4& cycle, unsigned threads) {
  return census_of(cycle, true, threads);
}

}  // namespace mesh4d::domain
