#include "domain/time_scale.h"

#include <algorithm>

namespace mesh4d::domain {
namespace {

// The area of frame t's label boundaries, from its voxel faces: every face between two labels
// once, and every face of a labelled voxel on the image's border (the outside is background).
// A staircase of faces has 3/2 the area of the smooth surface it follows when that surface's
// normals point every way alike (the mean of |n_x| + |n_y| + |n_z| over the sphere), as an
// organ's do, so the faces' area is scaled by 2/3.
double boundary_area(const LabelImage4& image, std::size_t t) {
  const Dims4& d = image.dims();
  const Vec4& s = image.spacing();
  const double face[3] = {s[1] * s[2], s[0] * s[2], s[0] * s[1]};
  double area = 0;
  for (std::size_t z = 0; z < d[2]; ++z)
    for (std::size_t y = 0; y < d[1]; ++y)
      for (std::size_t x = 0; x < d[0]; ++x) {
        const Label l = image.at(x, y, z, t);
        const std::size_t c[3] = {x, y, z};
        for (int a = 0; a < 3; ++a) {
          // The face towards the lower neighbor, and on the upper border the upper face too.
          std::size_t n[3] = {x, y, z};
          if (c[a] == 0) {
            area += l != 0 ? face[a] : 0;
          } else {
            --n[a];
            area += l != image.at(n[0], n[1], n[2], t) ? face[a] : 0;
          }
          if (c[a] + 1 == d[a] && l != 0) area += face[a];
        }
      }
  return area * 2 / 3;
}

}  // namespace

double boundary_motion_per_frame(const LabelImage4& image, bool periodic) {
  const Dims4& d = image.dims();
  const Vec4& s = image.spacing();
  const std::size_t frame_voxels = d[0] * d[1] * d[2];
  double largest = 0;
  double area = d[3] > 1 ? boundary_area(image, 0) : 0;
  const std::size_t pairs = d[3] > 1 ? d[3] - (periodic ? 0 : 1) : 0;
  for (std::size_t t = 0; t < pairs; ++t) {
    const std::size_t next = (t + 1) % d[3];
    const double next_area = boundary_area(image, next);
    std::size_t changed = 0;
    for (std::size_t i = 0; i < frame_voxels; ++i)
      changed += image.at(t * frame_voxels + i) != image.at(next * frame_voxels + i);
    // A frame without labels (the closing's padding, or before an object appears) borders a
    // time cap, which is no motion.
    if (area > 0 && next_area > 0)
      largest = std::max(
          largest, static_cast<double>(changed) * s[0] * s[1] * s[2] / ((area + next_area) / 2));
    area = next_area;
  }
  return largest;
}

double automatic_time_scale(const LabelImage4& image, double delta, bool periodic) {
  return std::max(delta, boundary_motion_per_frame(image, periodic));
}

}  // namespace mesh4d::domain
