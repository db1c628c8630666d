#include "domain/time_caps.h"

#include <algorithm>
#include <cmath>

namespace mesh4d::domain {

std::size_t cap_frames(double delta, double time_scale) {
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(delta / time_scale - 1e-9)));
}

LabelImage4 add_time_caps(const LabelImage4& image, std::size_t frames, TimeCaps* caps,
                          std::string* warning) {
  *caps = {};
  const std::vector<Label> labels = image.labels();
  std::vector<Label> foreground;
  for (Label l : labels)
    if (l != 0) foreground.push_back(l);
  if (frames == 0 || foreground.empty()) return image;
  if (foreground.size() > kMaxLabels / 2) {
    *warning = "the image has more than " + std::to_string(kMaxLabels / 2) +
               " labels, too many for ghost labels at the time caps: the end frames are closed "
               "with background half a frame out and come out smaller";
    return image;
  }
  const Dims4& d = image.dims();
  const std::size_t frame_voxels = d[0] * d[1] * d[2];
  const auto has_foreground = [&](std::size_t t) {
    for (std::size_t i = 0; i < frame_voxels; ++i)
      if (image.at(t * frame_voxels + i) != 0) return true;
    return false;
  };
  const std::size_t before = has_foreground(0) ? frames : 0;
  const std::size_t after = has_foreground(d[3] - 1) ? frames : 0;
  if (before + after == 0) return image;
  // Ghost labels above the image's largest, in the order of the labels they mirror.
  std::vector<Label> ghost_of(static_cast<std::size_t>(foreground.back()) + 1, 0);
  caps->real_of.assign(static_cast<std::size_t>(foreground.back()) + foreground.size() + 1, 0);
  for (std::size_t r = 0; r < foreground.size(); ++r) {
    const auto ghost = static_cast<Label>(foreground.back() + 1 + r);
    ghost_of[foreground[r]] = ghost;
    caps->real_of[ghost] = foreground[r];
  }
  caps->frames = frames;
  const double half = image.spacing()[3] / 2;
  if (before) caps->times.push_back(image.voxel_center(0, 0, 0, 0)[3] - half);
  if (after) caps->times.push_back(image.voxel_center(0, 0, 0, d[3] - 1)[3] + half);
  Vec4 origin = image.origin();
  origin[3] -= static_cast<double>(before) * image.spacing()[3];
  LabelImage4 out({d[0], d[1], d[2], d[3] + before + after}, image.spacing(), origin);
  for (std::size_t t = 0; t < d[3] + before + after; ++t) {
    const bool ghost = t < before || t >= before + d[3];
    const std::size_t source = t < before ? 0 : std::min(t - before, d[3] - 1);
    for (std::size_t i = 0; i < frame_voxels; ++i)
      if (const Label l = image.at(source * frame_voxels + i))
        out.set(t * frame_voxels + i, ghost ? ghost_of[l] : l);
  }
  return out;
}

}  // namespace mesh4d::domain
