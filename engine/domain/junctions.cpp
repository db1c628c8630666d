#include "domain/junctions.h"

#include <algorithm>
#include <cmath>

namespace mesh4d::domain {
namespace {

double dot(const Vec4& a, const Vec4& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
}

}  // namespace

std::optional<Point4> project_to_junction(const SurfaceOracle& oracle, const Point4& seed, Label a,
                                          Label b, Label c) {
  const Vec4& s = oracle.image().spacing();
  const double reach = std::sqrt(dot(s, s));
  Point4 x = seed;
  for (int iteration = 0; iteration < 40; ++iteration) {
    const double f0 = oracle.cut_value(x, a, b), f1 = oracle.cut_value(x, b, c);
    if (std::abs(f0) <= 1e-12 && std::abs(f1) <= 1e-12) {
      // A fourth label above the three would make this a point of another junction.
      const Label l = oracle.label_at(x);
      if (l != a && l != b && l != c) return std::nullopt;
      return x;
    }
    // Minimum-norm step of the 2×4 system J dx = −f: dx = −Jᵀ (J Jᵀ)⁻¹ f.
    const Vec4 g0 = oracle.cut_gradient(x, a, b), g1 = oracle.cut_gradient(x, b, c);
    const double m00 = dot(g0, g0), m01 = dot(g0, g1), m11 = dot(g1, g1);
    const double det = m00 * m11 - m01 * m01;
    if (!(det > 1e-12 * m00 * m11)) return std::nullopt;  // sheets (nearly) parallel here
    const double y0 = (m11 * f0 - m01 * f1) / det, y1 = (m00 * f1 - m01 * f0) / det;
    for (int k = 0; k < 4; ++k) x[k] -= y0 * g0[k] + y1 * g1[k];
    if (!(distance(x, seed) <= reach)) return std::nullopt;
  }
  return std::nullopt;
}

std::vector<JunctionPoint> sample_junctions(const SurfaceOracle& oracle,
                                            const std::function<bool(const Point4&)>& far_enough,
                                            const std::function<void(const Point4&)>& taken) {
  const LabelImage4& image = oracle.image();
  const Dims4& d = image.dims();
  std::vector<JunctionPoint> points;
  if (image.labels().size() < 3) return points;  // background and one label: no junction
  for (std::size_t t = 0; t + 1 < d[3]; ++t)
    for (std::size_t z = 0; z + 1 < d[2]; ++z)
      for (std::size_t y = 0; y + 1 < d[1]; ++y)
        for (std::size_t x = 0; x + 1 < d[0]; ++x) {
          // The labels of the cell's 16 corners, with their counts.
          std::array<Label, 16> label{};
          std::array<int, 16> count{};
          int distinct = 0;
          for (int corner = 0; corner < 16; ++corner) {
            const Label l = image.at(x + (corner & 1), y + ((corner >> 1) & 1),
                                     z + ((corner >> 2) & 1), t + ((corner >> 3) & 1));
            int k = 0;
            while (k < distinct && label[k] != l) ++k;
            if (k == distinct) label[distinct++] = l;
            ++count[k];
          }
          if (distinct < 3) continue;
          const Point4 lo = image.voxel_center(x, y, z, t);
          const Point4 hi = image.voxel_center(x + 1, y + 1, z + 1, t + 1);
          const Point4 seed{0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]),
                            0.5 * (lo[3] + hi[3])};
          if (!far_enough(seed)) continue;  // cheap: most seeds end here
          std::array<int, 16> order{};
          for (int k = 0; k < distinct; ++k) order[k] = k;
          std::sort(order.begin(), order.begin() + distinct, [&](int i, int j) {
            return count[i] != count[j] ? count[i] > count[j] : label[i] < label[j];
          });
          std::array<Label, 3> three{label[order[0]], label[order[1]], label[order[2]]};
          std::sort(three.begin(), three.end());
          const auto p = project_to_junction(oracle, seed, three[0], three[1], three[2]);
          if (!p || !far_enough(*p)) continue;
          taken(*p);
          points.push_back({*p, three});
        }
  return points;
}

}  // namespace mesh4d::domain
