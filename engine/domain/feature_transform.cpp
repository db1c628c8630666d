#include "domain/feature_transform.h"

#include <algorithm>
#include <limits>

#include "support/parallel_parts.h"

namespace mesh4d::domain {
namespace {

std::array<std::size_t, 4> strides_of(const Dims4& d) {
  return {1, d[0], d[0] * d[1], d[0] * d[1] * d[2]};
}

// One axis pass over the lines along `axis` numbered [first, last) (line L starts at voxel
// (L / stride) · len · stride + L % stride): each voxel takes the feature of the lower envelope
// of the parabolas w·(x - i)² + D(i) of the line's sites i (voxels that already have a feature).
// Lines are independent: the job's threads take a range each.
void envelope_pass(const LabelImage4& image, int axis, std::size_t first, std::size_t last,
                   std::vector<std::uint32_t>& feature, std::vector<double>& sq_dist) {
  const Dims4& d = image.dims();
  const auto stride = strides_of(d)[axis];
  const std::size_t len = d[axis];
  const double w = image.spacing()[axis] * image.spacing()[axis];
  const double inf = std::numeric_limits<double>::infinity();

  std::vector<std::size_t> v(len);  // positions of the envelope's parabolas
  std::vector<double> z(len + 1);   // where each parabola starts to be the lowest
  std::vector<std::uint32_t> line_feature(len);
  std::vector<double> line_dist(len);

  for (std::size_t line = first; line < last; ++line) {
    const std::size_t start = (line / stride) * len * stride + line % stride;
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

std::vector<std::uint32_t> feature_transform(const LabelImage4& image, unsigned threads) {
  const std::size_t n = image.voxel_count();
  std::vector<std::uint32_t> feature(n, kNoFeature);
  std::vector<double> sq_dist(n, 0.0);
  // A share of fewer voxels is not worth a thread.
  constexpr std::size_t kMinShare = std::size_t{1} << 18;
  const unsigned parts = support::parts_for(n, kMinShare, threads);
  // Surface voxels: those with a face neighbor of another label; each part takes whole rows
  // along x and writes only its own voxels.
  const Dims4& d = image.dims();
  const auto stride = strides_of(d);
  support::run_parts(parts, [&](unsigned part) {
    const auto [first, last] = support::part_range(n / d[0], part, parts);
    for (std::size_t row = first; row < last; ++row) {
      const std::size_t c[4] = {0, row % d[1], (row / d[1]) % d[2], row / (d[1] * d[2])};
      for (std::size_t x = 0, i = row * d[0]; x < d[0]; ++x, ++i) {
        const Label own = image.at(i);
        bool surface =
            (x > 0 && image.at(i - 1) != own) || (x + 1 < d[0] && image.at(i + 1) != own);
        for (int a = 1; a < 4 && !surface; ++a)
          surface = (c[a] > 0 && image.at(i - stride[a]) != own) ||
                    (c[a] + 1 < d[a] && image.at(i + stride[a]) != own);
        if (surface) feature[i] = static_cast<std::uint32_t>(i);
      }
    }
  });
  for (int axis = 0; axis < 4; ++axis) {
    const std::size_t lines = n / image.dims()[axis];
    support::run_parts(parts, [&](unsigned part) {
      const auto [first, last] = support::part_range(lines, part, parts);
      envelope_pass(image, axis, first, last, feature, sq_dist);
    });
  }
  return feature;
}

}  // namespace mesh4d::domain
