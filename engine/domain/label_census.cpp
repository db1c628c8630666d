#include "domain/label_census.h"

#include "domain/label_pieces.h"

namespace mesh4d::domain {

LabelCensus take_census(const LabelImage4& image) {
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
  std::vector<FacePieces::Piece> face;
  for (const FacePieces::Piece& p : label_function_pieces(image, &face).pieces)
    ++by_label[p.label].components;
  for (const FacePieces::Piece& p : face) ++by_label[p.label].face_components;
  for (auto& [l, per] : by_label) {
    per.volume = static_cast<double>(per.voxels) * voxel3 * s[3];
    census.labels.push_back(per);
  }
  return census;
}

}  // namespace mesh4d::domain
