#include "domain/time_extension.h"

#include <algorithm>
#include <string>

namespace mesh4d::domain {

LabelImage4 extend_time(const LabelImage4& image, std::size_t frames) {
  if (frames > kMaxTimeExtension)
    throw ImageError("time extension of " + std::to_string(frames) + " frames: at most " +
                     std::to_string(kMaxTimeExtension));
  const Dims4& d = image.dims();
  Vec4 origin = image.origin();
  origin[3] -= static_cast<double>(frames) * image.spacing()[3];
  LabelImage4 out({d[0], d[1], d[2], d[3] + 2 * frames}, image.spacing(), origin);
  const std::size_t frame_voxels = d[0] * d[1] * d[2];
  for (std::size_t t = 0; t < d[3] + 2 * frames; ++t) {
    const std::size_t source = std::min(d[3] - 1, t < frames ? 0 : t - frames);
    for (std::size_t i = 0; i < frame_voxels; ++i)
      if (const Label l = image.at(source * frame_voxels + i)) out.set(t * frame_voxels + i, l);
  }
  return out;
}

}  // namespace mesh4d::domain
