#include "domain/label_census.h"

#include <algorithm>
#include <cstdint>

namespace mesh4d::domain {

LabelCensus take_census(const LabelImage4& image) {
  const auto& d = image.dims();
  const auto& s = image.spacing();
  const std::size_t n = image.voxel_count();
  const double voxel3 = s[0] * s[1] * s[2];
  LabelCensus census;
  std::map<Label, LabelCensus::PerLabel> by_label;
  census.frame_volumes.resize(d[3]);
  for (std::size_t t = 0; t < d[3]; ++t)
    census.frame_times.push_back(image.voxel_center(0, 0, 0, t)[3]);

  // Pieces by flood fill over the eight face neighbors; a byte per voxel marks the visited.
  const std::size_t stride[4] = {1, d[0], d[0] * d[1], d[0] * d[1] * d[2]};
  std::vector<std::uint8_t> seen(n, 0);
  std::vector<std::size_t> frontier;
  for (std::size_t t = 0, i = 0; t < d[3]; ++t)
    for (std::size_t z = 0; z < d[2]; ++z)
      for (std::size_t y = 0; y < d[1]; ++y)
        for (std::size_t x = 0; x < d[0]; ++x, ++i) {
          const Label l = image.at(i);
          if (l == 0) continue;
          LabelCensus::PerLabel& per = by_label[l];
          per.label = l;
          ++per.voxels;
          census.frame_volumes[t][l] += voxel3;
          if (seen[i]) continue;
          ++per.components;
          seen[i] = 1;
          frontier.assign(1, i);
          while (!frontier.empty()) {
            const std::size_t j = frontier.back();
            frontier.pop_back();
            std::size_t c[4] = {j % d[0], j / d[0] % d[1], j / (d[0] * d[1]) % d[2],
                                j / (d[0] * d[1] * d[2])};
            for (int a = 0; a < 4; ++a) {
              if (c[a] > 0 && !seen[j - stride[a]] && image.at(j - stride[a]) == l)
                seen[j - stride[a]] = 1, frontier.push_back(j - stride[a]);
              if (c[a] + 1 < d[a] && !seen[j + stride[a]] && image.at(j + stride[a]) == l)
                seen[j + stride[a]] = 1, frontier.push_back(j + stride[a]);
            }
          }
        }
  for (auto& [l, per] : by_label) {
    per.volume = static_cast<double>(per.voxels) * voxel3 * s[3];
    census.labels.push_back(per);
  }
  return census;
}

}  // namespace mesh4d::domain
