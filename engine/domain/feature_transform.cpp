#include "domain/feature_transform.h"

#include <limits>

namespace mesh4d::domain {
namespace {

std::array<std::size_t, 4> strides_of(const Dims4& d) {
  return {1, d[0], d[0] * d[1], d[0] * d[1] * d[2]};
}

// One axis pass over every line along `axis`: each voxel takes the feature of the lower envelope
// of the parabolas w·(x - i)² + D(i) of the line's sites i (voxels that already have a feature).
void envelope_pass(const LabelImage4& image, int axis, std::vector<std::uint32_t>& feature,
                   std::vector<double>& sq_dist) {
  const Dims4& d = image.dims();
  const auto stride = strides_of(d)[axis];
  const std::size_t len = d[axis];
  const std::size_t n = image.voxel_count();
  const double w = image.spacing()[axis] * image.spacing()[axis];
  const double inf = std::numeric_limits<double>::infinity();

  std::vector<std::size_t> v(len);  // positions of the envelope's parabolas
  std::vector<double> z(len + 1);   // where each parabola starts to be the lowest
  std::vector<std::uint32_t> line_feature(len);
  std::vector<double> line_dist(len);

  const std::size_t block = len * stride;
  for (std::size_t outer = 0; outer < n; outer += block) {
    for (std::size_t inner = 0; inner < stride; ++inner) {
      const std::size_t start = outer + inner;
      for (std::size_t i = 0; i < len; ++i) {
        line_feature[i] = feature[start + i * stride];
        line_dist[i] = sq_dist[start + i * stride];
      }
      // Lower envelope of the sites' parabolas.
      std::size_t k = 0;
      bool any = false;
      for (std::size_t q = 0; q < len; ++q) {
        if (line_feature[q] == kNoFeature) continue;
        if (!any) {
          v[0] = q;
          z[0] = -inf;
          z[1] = inf;
          any = true;
          continue;
        }
        // Where q's parabola passes below v[k]'s; drop the parabolas it hides (z[0] = -∞ stops
        // the loop at the first one).
        const double fq = line_dist[q] + w * double(q) * double(q);
        auto crossing = [&](std::size_t p) {
          const double pd = double(p);
          return (fq - (line_dist[p] + w * pd * pd)) / (2 * w * (double(q) - pd));
        };
        double s = crossing(v[k]);
        while (s <= z[k]) s = crossing(v[--k]);
        ++k;
        v[k] = q;
        z[k] = s;
        z[k + 1] = inf;
      }
      if (!any) continue;
      std::size_t e = 0;
      for (std::size_t x = 0; x < len; ++x) {
        while (z[e + 1] < double(x)) ++e;
        const double dx = double(x) - double(v[e]);
        feature[start + x * stride] = line_feature[v[e]];
        sq_dist[start + x * stride] = w * dx * dx + line_dist[v[e]];
      }
    }
  }
}

}  // namespace

bool is_surface_voxel(const LabelImage4& image, std::size_t i) {
  const Dims4& d = image.dims();
  const auto stride = strides_of(d);
  const Label own = image.at(i);
  std::size_t rest = i;
  for (int a = 0; a < 4; ++a) {
    const std::size_t c = rest % d[a];
    rest /= d[a];
    if (c > 0 && image.at(i - stride[a]) != own) return true;
    if (c + 1 < d[a] && image.at(i + stride[a]) != own) return true;
  }
  return false;
}

std::vector<std::uint32_t> feature_transform(const LabelImage4& image) {
  const std::size_t n = image.voxel_count();
  std::vector<std::uint32_t> feature(n, kNoFeature);
  std::vector<double> sq_dist(n, 0.0);
  // Surface voxels: compare each voxel with its +1 neighbor along every axis; a difference makes
  // both surface voxels.
  const Dims4& d = image.dims();
  const auto stride = strides_of(d);
  for (std::size_t t = 0, i = 0; t < d[3]; ++t)
    for (std::size_t z = 0; z < d[2]; ++z)
      for (std::size_t y = 0; y < d[1]; ++y)
        for (std::size_t x = 0; x < d[0]; ++x, ++i) {
          const Label own = image.at(i);
          const std::size_t c[4] = {x, y, z, t};
          for (int a = 0; a < 4; ++a) {
            if (c[a] + 1 >= d[a]) continue;
            const std::size_t j = i + stride[a];
            if (image.at(j) != own) {
              feature[i] = static_cast<std::uint32_t>(i);
              feature[j] = static_cast<std::uint32_t>(j);
            }
          }
        }
  for (int axis = 0; axis < 4; ++axis) envelope_pass(image, axis, feature, sq_dist);
  return feature;
}

}  // namespace mesh4d::domain
